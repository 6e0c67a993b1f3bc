"""The robot model: frozen, typed dataclasses for everything a URDF holds.

Every element keeps where it came from (:class:`Source`): the line in the URDF, and — when
the URDF was produced by xacro — the xacro line that produced it. Sources never take part in
equality, so a model written and parsed back compares equal.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from belvedere.errors import SourceLocation

__all__ = [
    "Actuator",
    "Box",
    "Calibration",
    "Collision",
    "Cylinder",
    "Dynamics",
    "GazeboExtension",
    "GazeboPlugin",
    "Geometry",
    "Inertial",
    "Joint",
    "JointType",
    "Limit",
    "Link",
    "Material",
    "Mesh",
    "Mimic",
    "Pose",
    "SafetyController",
    "Source",
    "Sphere",
    "Transmission",
    "TransmissionJoint",
    "Vec3",
    "Visual",
    "XmlData",
]

Vec3 = tuple[float, float, float]
JointType = Literal["revolute", "continuous", "prismatic", "fixed", "floating", "planar"]
JOINT_TYPES: tuple[JointType, ...] = (
    "revolute",
    "continuous",
    "prismatic",
    "fixed",
    "floating",
    "planar",
)


@dataclass(frozen=True, slots=True)
class Source:
    """Where an element came from."""

    urdf: SourceLocation | None = None
    """The element's line in the URDF text."""
    xacro: SourceLocation | None = None
    """The xacro line that produced it, when the URDF came from xacro."""

    @property
    def best(self) -> SourceLocation | None:
        """What to show a user: the xacro line if there is one, else the URDF line."""
        return self.xacro or self.urdf

    def __str__(self) -> str:
        return str(self.best) if self.best else "<unknown>"


@dataclass(frozen=True, slots=True)
class Pose:
    """An ``<origin>``: translation (m) then fixed-axis roll, pitch, yaw (rad)."""

    xyz: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)


@dataclass(frozen=True, slots=True)
class Box:
    size: Vec3


@dataclass(frozen=True, slots=True)
class Cylinder:
    radius: float
    length: float


@dataclass(frozen=True, slots=True)
class Sphere:
    radius: float


@dataclass(frozen=True, slots=True)
class Mesh:
    filename: str
    """As written: ``package://pkg/…``, ``file://…`` or a path relative to the URDF."""
    scale: Vec3 = (1.0, 1.0, 1.0)


Geometry = Box | Cylinder | Sphere | Mesh


@dataclass(frozen=True, slots=True)
class Material:
    """A named colour and/or texture (global, or inline in a visual)."""

    name: str
    rgba: tuple[float, float, float, float] | None = None
    texture: str | None = None
    source: Source = field(default_factory=Source, compare=False, repr=False)


@dataclass(frozen=True, slots=True)
class Visual:
    geometry: Geometry
    origin: Pose = Pose()
    name: str | None = None
    material_name: str | None = None
    material: Material | None = None
    """The material as defined inline (``<material name=…><color …/></material>``), if so."""
    source: Source = field(default_factory=Source, compare=False, repr=False)


@dataclass(frozen=True, slots=True)
class Collision:
    geometry: Geometry
    origin: Pose = Pose()
    name: str | None = None
    source: Source = field(default_factory=Source, compare=False, repr=False)


@dataclass(frozen=True, slots=True)
class Inertial:
    mass: float
    ixx: float
    ixy: float
    ixz: float
    iyy: float
    iyz: float
    izz: float
    origin: Pose = Pose()
    source: Source = field(default_factory=Source, compare=False, repr=False)


@dataclass(frozen=True, slots=True)
class Link:
    name: str
    inertial: Inertial | None = None
    visuals: tuple[Visual, ...] = ()
    collisions: tuple[Collision, ...] = ()
    source: Source = field(default_factory=Source, compare=False, repr=False)


@dataclass(frozen=True, slots=True)
class Limit:
    effort: float
    velocity: float
    lower: float = 0.0
    upper: float = 0.0


@dataclass(frozen=True, slots=True)
class Dynamics:
    damping: float = 0.0
    friction: float = 0.0


@dataclass(frozen=True, slots=True)
class Mimic:
    joint: str
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True, slots=True)
class SafetyController:
    k_velocity: float
    k_position: float = 0.0
    soft_lower_limit: float = 0.0
    soft_upper_limit: float = 0.0


@dataclass(frozen=True, slots=True)
class Calibration:
    rising: float | None = None
    falling: float | None = None


@dataclass(frozen=True, slots=True)
class Joint:
    name: str
    type: JointType
    parent: str
    child: str
    origin: Pose = Pose()
    axis: Vec3 = (1.0, 0.0, 0.0)
    limit: Limit | None = None
    dynamics: Dynamics | None = None
    mimic: Mimic | None = None
    safety_controller: SafetyController | None = None
    calibration: Calibration | None = None
    source: Source = field(default_factory=Source, compare=False, repr=False)

    @property
    def movable(self) -> bool:
        return self.type != "fixed"

    @property
    def position_range(self) -> tuple[float, float] | None:
        """Where a revolute or prismatic joint may move, ``(lower, upper)``; None when nothing
        bounds it: another type, no ``<limit>``, or limits the wrong way round, which
        urdfdom accepts and Gazebo's ODE then ignores both of (:attr:`inverted_limits`)."""
        limit = self.limit
        if limit is None or self.type not in ("revolute", "prismatic"):
            return None
        if limit.lower > limit.upper:
            return None
        return limit.lower, limit.upper

    @property
    def inverted_limits(self) -> str | None:
        """What ``check``, the simulator and the viewer say of a revolute or prismatic joint
        whose lower limit is above its upper one; None if it has no such limits."""
        limit = self.limit
        if limit is None or self.type not in ("revolute", "prismatic"):
            return None
        if limit.lower <= limit.upper:
            return None
        return (
            f"joint '{self.name}': lower limit {limit.lower} > upper limit {limit.upper}, so it "
            "moves without limits (Gazebo's ODE ignores limits the wrong way round, and so do "
            "belvedere's simulator and viewer)"
        )


@dataclass(frozen=True, slots=True)
class TransmissionJoint:
    name: str
    hardware_interfaces: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class Actuator:
    name: str
    mechanical_reduction: float | None = None
    hardware_interfaces: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class Transmission:
    """``<transmission>`` in the current format, or the ROS 1 legacy one (``legacy=True``:
    ``<type>`` as an attribute, ``<joint>``/``<actuator>`` without hardware interfaces)."""

    name: str
    type: str
    joints: tuple[TransmissionJoint, ...] = ()
    actuators: tuple[Actuator, ...] = ()
    legacy: bool = False
    source: Source = field(default_factory=Source, compare=False, repr=False)


@dataclass(frozen=True, slots=True)
class XmlData:
    """A piece of XML kept as data: plugin parameters, sensor blocks."""

    tag: str
    attrs: tuple[tuple[str, str], ...] = ()
    text: str = ""
    children: tuple[XmlData, ...] = ()
    source: Source = field(default_factory=Source, compare=False, repr=False)

    def attr(self, name: str) -> str | None:
        return next((v for k, v in self.attrs if k == name), None)

    def child(self, tag: str) -> XmlData | None:
        return next((c for c in self.children if c.tag == tag), None)

    def child_text(self, tag: str) -> str | None:
        c = self.child(tag)
        return c.text.strip() if c is not None else None


@dataclass(frozen=True, slots=True)
class GazeboPlugin:
    name: str
    filename: str
    params: tuple[XmlData, ...] = ()
    source: Source = field(default_factory=Source, compare=False, repr=False)

    def param(self, tag: str) -> str | None:
        """The text of a parameter element (``<leftJoint>left_wheel_joint</leftJoint>``)."""
        return next((p.text.strip() for p in self.params if p.tag == tag), None)


@dataclass(frozen=True, slots=True)
class GazeboExtension:
    """One ``<gazebo>`` block: for a link or joint (``reference``) or the robot (None)."""

    reference: str | None
    properties: tuple[tuple[str, str], ...] = ()
    """Simple settings in order: ``(("material", "Gazebo/Blue"), ("mu1", "0.2"))``."""
    plugins: tuple[GazeboPlugin, ...] = ()
    sensors: tuple[XmlData, ...] = ()
    other: tuple[XmlData, ...] = ()
    """Anything else with structure, kept as data."""
    source: Source = field(default_factory=Source, compare=False, repr=False)

    def property(self, name: str) -> str | None:
        return next((v for k, v in self.properties if k == name), None)
