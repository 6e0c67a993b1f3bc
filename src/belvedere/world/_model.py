"""``WorldModel``: what a Gazebo world holds, as typed, immutable data with source lines.

Poses are resolved when the world is read: every model's pose is in the world frame, every
link's pose in its model's frame, every shape's pose in its link's frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from belvedere.description.urdf import (
    Box,
    Cylinder,
    GazeboPlugin,
    Inertial,
    Mesh,
    Pose,
    Sphere,
    Vec3,
    XmlData,
)
from belvedere.errors import ParseError, SourceLocation

__all__ = [
    "Attenuation",
    "Light",
    "Material",
    "Physics",
    "Plane",
    "Polyline",
    "SDFError",
    "Scene",
    "Shape",
    "Surface",
    "WorldFrame",
    "WorldGeometry",
    "WorldJoint",
    "WorldLink",
    "WorldModel",
    "WorldModelEntry",
]

RGBA = tuple[float, float, float, float]


class SDFError(ParseError):
    """A world or model file that cannot be read."""


@dataclass(frozen=True, slots=True)
class Plane:
    normal: Vec3 = (0.0, 0.0, 1.0)
    size: tuple[float, float] = (100.0, 100.0)


@dataclass(frozen=True, slots=True)
class Polyline:
    """A prism: the polygon ``points`` (x, y) extruded up by ``height`` (building editor)."""

    points: tuple[tuple[float, float], ...]
    height: float


WorldGeometry = Box | Cylinder | Sphere | Mesh | Plane | Polyline
"""Meshes carry an absolute file path once the world is read."""


@dataclass(frozen=True, slots=True)
class Surface:
    """Contact properties (ODE's ``<surface>``)."""

    mu: float = 1.0
    mu2: float = 1.0
    kp: float | None = None
    kd: float | None = None
    min_depth: float | None = None
    max_vel: float | None = None


@dataclass(frozen=True, slots=True)
class Material:
    """How a visual reflects light (SDF ``<material>``, Gazebo's named materials): the
    colours OGRE's fixed-function Phong shading of Gazebo classic uses."""

    ambient: RGBA = (1.0, 1.0, 1.0, 1.0)
    """Reflects the scene's ambient light."""
    diffuse: RGBA = (1.0, 1.0, 1.0, 1.0)
    """Reflects each light's diffuse colour (Lambert)."""
    specular: RGBA = (0.0, 0.0, 0.0, 1.0)
    emissive: RGBA = (0.0, 0.0, 0.0, 1.0)
    shininess: float = 0.0
    """Phong exponent (OGRE's; 0 = a broad highlight)."""


@dataclass(frozen=True, slots=True)
class Shape:
    """A collision or visual of a link."""

    name: str
    geometry: WorldGeometry
    pose: Pose = Pose()
    surface: Surface | None = None
    rgba: RGBA | None = None
    material: Material | None = None
    """A visual's full material (``rgba`` is its diffuse colour)."""
    source: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class WorldLink:
    name: str
    pose: Pose = Pose()
    """In the model's frame."""
    inertial: Inertial | None = None
    collisions: tuple[Shape, ...] = ()
    visuals: tuple[Shape, ...] = ()
    gravity: bool = True
    kinematic: bool = False
    source: SourceLocation | None = field(default=None, compare=False)
    sensors: tuple[XmlData, ...] = ()
    """Its ``<sensor>``s as written (each ``<pose>`` in the link's frame): a robot saved in
    the world keeps its laser and cameras, with their plugins."""


@dataclass(frozen=True, slots=True)
class WorldJoint:
    name: str
    type: str
    parent: str
    """A link of the model, or ``world``."""
    child: str
    pose: Pose = Pose()
    """In the child link's frame (whatever frame the file wrote it in)."""
    axis: Vec3 = (0.0, 0.0, 1.0)
    """In the child link's frame."""
    lower: float | None = None
    upper: float | None = None
    damping: float = 0.0
    friction: float = 0.0
    source: SourceLocation | None = field(default=None, compare=False)
    effort: float | None = None
    """``<limit><effort>`` (None: not written; SDF's default, -1, is no limit)."""
    velocity: float | None = None


@dataclass(frozen=True, slots=True)
class WorldFrame:
    """An explicit ``<frame>`` (SDF 1.7): where it is and what it moves with."""

    name: str
    pose: Pose = Pose()
    """In its model's frame (a world frame: in the world frame)."""
    attached_to: str | None = None
    """The link it moves with (``nested::link`` for one of a nested model); None: the world."""
    source: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class WorldModelEntry:
    """One ``<model>`` of the world (included ones resolved and flattened)."""

    name: str
    pose: Pose = Pose()
    """In the world frame."""
    static: bool = False
    links: tuple[WorldLink, ...] = ()
    joints: tuple[WorldJoint, ...] = ()
    uri: str | None = None
    """``model://…`` when it came from an ``<include>``."""
    source: SourceLocation | None = field(default=None, compare=False)
    frames: tuple[WorldFrame, ...] = ()
    """Its explicit ``<frame>``s, nested models' ones as ``nested::name``."""
    canonical_link: str | None = None
    """The link the model frame is attached to (SDF 1.7 ``canonical_link``; by default the
    first link, or a nested model's canonical link)."""
    plugins: tuple[GazeboPlugin, ...] = ()
    """Its model plugins as written (a robot saved in the world keeps its diff drive)."""

    @property
    def robot(self) -> bool:
        """A robot, as a saved world keeps one: plugins or sensors of its own (the
        simulation spawns it as a robot, its joints moving)."""
        return bool(self.plugins) or any(link.sensors for link in self.links)

    def link(self, name: str) -> WorldLink | None:
        return next((link for link in self.links if link.name == name), None)


@dataclass(frozen=True, slots=True)
class Physics:
    max_step_size: float = 0.001
    real_time_update_rate: float = 1000.0
    real_time_factor: float = 1.0
    gravity: Vec3 = (0.0, 0.0, -9.8)


@dataclass(frozen=True, slots=True)
class Attenuation:
    """A point or spot light's fall-off with distance ``d``: ``1 / (constant + linear d +
    quadratic d²)``, none beyond ``range``."""

    range: float = 10.0
    constant: float = 1.0
    linear: float = 1.0
    quadratic: float = 0.0


@dataclass(frozen=True, slots=True)
class Light:
    name: str
    type: str = "directional"
    """``directional``, ``point`` or ``spot``."""
    pose: Pose = Pose()
    diffuse: RGBA = (0.8, 0.8, 0.8, 1.0)
    direction: Vec3 = (-0.5, 0.1, -0.9)
    """In the light's frame (``pose``)."""
    cast_shadows: bool = True
    specular: RGBA = (0.1, 0.1, 0.1, 1.0)
    attenuation: Attenuation = Attenuation()
    spot_inner_angle: float = 0.0
    spot_outer_angle: float = 0.0
    spot_falloff: float = 0.0
    source: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Scene:
    """A world's ``<scene>``: Gazebo classic's defaults, except shadows, which are off
    unless the world asks for them (cameras render several times faster without)."""

    ambient: RGBA = (0.4, 0.4, 0.4, 1.0)
    background: RGBA = (0.7, 0.7, 0.7, 1.0)
    shadows: bool = False


@dataclass(frozen=True, slots=True)
class WorldModel:
    """A world: physics settings, models, lights and the scene they are seen in."""

    name: str = "default"
    physics: Physics = Physics()
    models: tuple[WorldModelEntry, ...] = ()
    lights: tuple[Light, ...] = ()
    frames: tuple[WorldFrame, ...] = ()
    """World-level ``<frame>``s, posed in the world frame."""
    scene: Scene = Scene()
    path: str | None = None
    sdf_version: str = "1.6"
    warnings: tuple[str, ...] = field(default=(), compare=False)
    kept: tuple[str, ...] = field(default=(), compare=False)
    """The world's elements a saved world writes back as they were (``<gui>``'s camera,
    ``<physics>``'s solver settings, ``<scene>``'s sky, world plugins…), as XML text."""

    def model(self, name: str) -> WorldModelEntry | None:
        return next((m for m in self.models if m.name == name), None)
