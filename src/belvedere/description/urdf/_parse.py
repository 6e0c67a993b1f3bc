"""URDF text → :class:`RobotModel`, with urdfdom's verdicts.

What urdfdom (ROS's parser, ``check_urdf``) rejects, we reject: a missing robot name, no
links, a joint that does not parse, duplicate names, links a joint names but nobody defines,
two roots or none. What urdfdom only logs and skips (a visual without a usable geometry, a
material without a colour, an unparsable inertial), we skip too — with a warning that says
so and where. Numbers follow urdfdom: leading spaces are fine, anything after the number is
not, and ``inf``/``nan``/hex are not numbers. One verdict is stricter than urdfdom's: a number
too large for a double (``1e309``) is an error wherever it is, where urdfdom drops the
inertial or visual holding it and carries on — a silently massless link is worse than a stop.
"""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Final, Literal, TypeVar

from belvedere.description.urdf._model import (
    JOINT_TYPES,
    Actuator,
    Box,
    Calibration,
    Collision,
    Cylinder,
    Dynamics,
    GazeboExtension,
    GazeboPlugin,
    Geometry,
    Inertial,
    Joint,
    JointType,
    Limit,
    Link,
    Material,
    Mesh,
    Mimic,
    Pose,
    SafetyController,
    Source,
    Sphere,
    Transmission,
    TransmissionJoint,
    Vec3,
    Visual,
    XmlData,
)
from belvedere.errors import SourceLocation
from belvedere.xmldom import CData, Document, Element, Text

__all__ = ["Diagnostic", "ParsedRobot", "parse_robot"]

_T = TypeVar("_T")
_DOUBLE: Final = re.compile(r"\s*[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\Z")
_MAX_DOUBLE: Final = sys.float_info.max


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """A finding about the input: ``error`` (urdfdom rejects the file) or ``warning``."""

    severity: Literal["error", "warning", "note"]
    """A note tells what was understood, fine as it is (``-q`` hides it)."""
    message: str
    location: SourceLocation | None = None
    legacy: str | None = None
    """The tag, for xacro's warning about one legacy unprefixed tag or macro call (shown
    summed up: :func:`belvedere.description.xacro.legacy_summary`)."""

    def __str__(self) -> str:
        where = f"{self.location}: " if self.location else ""
        return f"{where}{self.severity}: {self.message}"


class _InvalidError(Exception):
    """A part that does not parse (urdfdom returns false for it)."""


class _NonFiniteError(_InvalidError):
    """A number that overflows a double: an error wherever it is (see the module docstring)."""


class _FatalError(Exception):
    """urdfdom gives up on the whole file."""


@dataclass
class ParsedRobot:
    """What parsing found: the parts (document order) and the diagnostics."""

    name: str = ""
    links: list[Link] = field(default_factory=list)
    joints: list[Joint] = field(default_factory=list)
    materials: list[Material] = field(default_factory=list)
    transmissions: list[Transmission] = field(default_factory=list)
    gazebo: list[GazeboExtension] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    source: Source = field(default_factory=Source)
    path: str | None = None
    """The file parsed (a xacro file when the URDF came from one)."""

    @property
    def fatal(self) -> bool:
        return any(d.severity == "error" for d in self.diagnostics)


def parse_robot(
    doc: Document, *, xacro_location: Callable[[Element], SourceLocation | None] | None = None
) -> ParsedRobot:
    """Parse a URDF document; check ``.fatal`` / ``.diagnostics`` for the verdict."""
    return _Parser(xacro_location).run(doc)


def _number(text: str | None, what: str) -> float:
    if text is None or not _DOUBLE.match(text):
        msg = f"{what} [{text}] is not a valid number"
        raise _InvalidError(msg)
    return _finite(float(text), f"{what} [{text.strip()}]")


def _finite(value: float, what: str) -> float:
    if not math.isfinite(value):
        msg = f"{what} is too large for a double (the limit is ±{_MAX_DOUBLE:.17g})"
        raise _NonFiniteError(msg)
    return value


def _vector(text: str, what: str, n: int = 3) -> tuple[float, ...]:
    pieces = [p for p in text.split(" ") if p != ""]
    values = []
    for p in pieces:
        if not _DOUBLE.match(p):
            msg = f"{what}: unable to parse component [{p}] to a number in [{text}]"
            raise _InvalidError(msg)
        values.append(_finite(float(p), f"{what}: component [{p}] of [{text}]"))
    if len(values) != n:
        msg = f"{what}: found {len(values)} numbers but {n} expected in [{text}]"
        raise _InvalidError(msg)
    return tuple(values)


def _vec3(text: str, what: str) -> Vec3:
    x, y, z = _vector(text, what)
    return (x, y, z)


_NONE: Final[list[Element]] = []


def _index(el: Element) -> dict[str, list[Element]]:
    """Children by tag, in order (built once per element)."""
    out: dict[str, list[Element]] = {}
    for c in el.elements():
        out.setdefault(c.tag, []).append(c)
    return out


def _text(el: Element) -> str:
    return "".join(c.data for c in el.children() if isinstance(c, Text | CData))


class _Parser:
    def __init__(self, xacro_location: Callable[[Element], SourceLocation | None] | None) -> None:
        self.xacro_location = xacro_location
        self.out = ParsedRobot()
        self._kids: dict[int, dict[str, list[Element]]] = {}

    def all(self, el: Element, tag: str) -> list[Element]:
        kids = self._kids.get(id(el))
        if kids is None:
            kids = self._kids[id(el)] = _index(el)
        return kids.get(tag, _NONE)

    def first(self, el: Element, tag: str) -> Element | None:
        found = self.all(el, tag)
        return found[0] if found else None

    def source(self, el: Element) -> Source:
        return Source(el.loc, self.xacro_location(el) if self.xacro_location else None)

    def report(self, severity: Literal["error", "warning"], message: str, el: Element) -> None:
        self.out.diagnostics.append(Diagnostic(severity, message, self.source(el).best))

    def fatal(self, message: str, where: Element | Source) -> _FatalError:
        source = where if isinstance(where, Source) else self.source(where)
        self.out.diagnostics.append(Diagnostic("error", message, source.best))
        return _FatalError(message)

    # --- the robot ----------------------------------------------------------------------------
    def run(self, doc: Document) -> ParsedRobot:
        robot = doc.root
        try:
            if robot.tag != "robot":
                msg = f"the root element is <{robot.tag}>, not <robot>: this is not a URDF"
                raise self.fatal(msg, robot)
            if "name" not in robot.attrs:
                msg = "no name given for the robot (<robot name=…>)"
                raise self.fatal(msg, robot)
            self.out.name = robot.attrs["name"]
            self.out.source = self.source(robot)
            self.materials(robot)
            self.links(robot)
            self.joints(robot)
            self.tree(robot)
        except _FatalError:
            pass
        for el in self.all(robot, "transmission"):
            self.transmission(el)
        for el in self.all(robot, "gazebo"):
            self.out.gazebo.append(self.gazebo(el))
        return self.out

    def materials(self, robot: Element) -> None:
        names: set[str] = set()
        for el in self.all(robot, "material"):
            material = self.material(el, only_name_ok=False)
            if material.name in names:
                msg = f"material '{material.name}' is not unique"
                raise self.fatal(msg, el)
            names.add(material.name)
            self.out.materials.append(material)

    def material(self, el: Element, *, only_name_ok: bool) -> Material:
        name = el.attrs.get("name")
        if name is None:
            self.report("warning", "material must have a name attribute (urdfdom ignores it)", el)
            return Material("", source=self.source(el))
        rgba: tuple[float, float, float, float] | None = None
        texture: str | None = None
        tex = self.first(el, "texture")
        if tex is not None and "filename" in tex.attrs:
            texture = tex.attrs["filename"]
        color = self.first(el, "color")
        if color is not None and "rgba" in color.attrs:
            try:
                r, g, b, a = _vector(color.attrs["rgba"], f"material [{name}] color rgba", 4)
                rgba = (r, g, b, a)
            except _NonFiniteError as err:
                self.report("error", f"material [{name}] color: {err}", color)
            except _InvalidError as err:
                self.report("warning", f"{err} (urdfdom ignores the colour)", color)
        if rgba is None and texture is None and not only_name_ok:
            self.report("warning", f"material [{name}] has neither a colour nor a texture", el)
        return Material(name, rgba, texture, self.source(el))

    # --- links ---------------------------------------------------------------------------------
    def links(self, robot: Element) -> None:
        names: set[str] = set()
        known = {m.name for m in self.out.materials}
        for el in self.all(robot, "link"):
            link = self.link(el)
            if link.name in names:
                msg = f"link '{link.name}' is not unique"
                raise self.fatal(msg, el)
            names.add(link.name)
            # urdfdom registers the inline material of a link's first visual.
            if link.visuals:
                first = link.visuals[0]
                if first.material_name and first.material_name not in known:
                    assert first.material is not None  # a material_name comes with one
                    known.add(first.material_name)
                    self.out.materials.append(first.material)
            self.out.links.append(link)
        if not self.out.links:
            msg = "no link elements found in the URDF"
            raise self.fatal(msg, robot)

    def link(self, el: Element) -> Link:
        name = el.attrs.get("name")
        if name is None:
            self.report("warning", "link without a name (urdfdom names it '')", el)
            return Link("", source=self.source(el))
        inertial = None
        visuals: list[Visual] = []
        collisions: list[Collision] = []
        stage = "inertial"
        part = self.first(el, "inertial")
        try:
            if part is not None:
                inertial = self.inertial(part)
            stage = "visual"
            for part in self.all(el, "visual"):
                visuals.append(self.visual(part))
            stage = "collision"
            for part in self.all(el, "collision"):
                collisions.append(self.collision(part))
        except _NonFiniteError as err:
            self.report("error", f"link [{name}] {stage}: {err}", part or el)
        except _InvalidError as err:
            rest = {
                "inertial": "its inertial, visuals and collisions",
                "visual": "this and the following visuals, and all collisions",
                "collision": "this and the following collisions",
            }[stage]
            self.report("warning", f"link [{name}]: {err}; urdfdom drops {rest}", el)
        return Link(name, inertial, tuple(visuals), tuple(collisions), self.source(el))

    def pose(self, el: Element | None, what: str) -> Pose:
        if el is None:
            return Pose()
        xyz = _vec3(el.attrs["xyz"], f"{what} origin xyz") if "xyz" in el.attrs else (0.0, 0.0, 0.0)
        rpy = _vec3(el.attrs["rpy"], f"{what} origin rpy") if "rpy" in el.attrs else (0.0, 0.0, 0.0)
        return Pose(xyz, rpy)

    def inertial(self, el: Element) -> Inertial:
        origin = self.pose(self.first(el, "origin"), "inertial")
        mass_el = self.first(el, "mass")
        if mass_el is None or "value" not in mass_el.attrs:
            msg = "inertial must have <mass value=…>"
            raise _InvalidError(msg)
        mass = _number(mass_el.attrs["value"], "inertial mass")
        inertia = self.first(el, "inertia")
        keys = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
        if inertia is None or any(k not in inertia.attrs for k in keys):
            msg = "inertial must have <inertia> with ixx, ixy, ixz, iyy, iyz, izz"
            raise _InvalidError(msg)
        ixx, ixy, ixz, iyy, iyz, izz = (_number(inertia.attrs[k], f"inertia {k}") for k in keys)
        return Inertial(mass, ixx, ixy, ixz, iyy, iyz, izz, origin, self.source(el))

    def geometry(self, el: Element | None) -> Geometry:
        if el is None:
            msg = "missing <geometry>"
            raise _InvalidError(msg)
        shape = el.first_element()
        if shape is None:
            msg = "<geometry> has no shape inside"
            raise _InvalidError(msg)
        a = shape.attrs
        if shape.tag == "box":
            if "size" not in a:
                msg = "box has no size attribute"
                raise _InvalidError(msg)
            return Box(_vec3(a["size"], "box size"))
        if shape.tag == "cylinder":
            if "radius" not in a or "length" not in a:
                msg = "cylinder must have both length and radius attributes"
                raise _InvalidError(msg)
            return Cylinder(
                _number(a["radius"], "cylinder radius"), _number(a["length"], "cylinder length")
            )
        if shape.tag == "sphere":
            if "radius" not in a:
                msg = "sphere must have a radius attribute"
                raise _InvalidError(msg)
            return Sphere(_number(a["radius"], "sphere radius"))
        if shape.tag == "mesh":
            if "filename" not in a:
                msg = "mesh must have a filename attribute"
                raise _InvalidError(msg)
            scale = _vec3(a["scale"], "mesh scale") if "scale" in a else (1.0, 1.0, 1.0)
            return Mesh(a["filename"], scale)
        msg = f"unknown geometry type <{shape.tag}> (expected box, cylinder, sphere or mesh)"
        raise _InvalidError(msg)

    def visual(self, el: Element) -> Visual:
        origin = self.pose(self.first(el, "origin"), "visual")
        geometry = self.geometry(self.first(el, "geometry"))
        material_name = None
        material = None
        mat = self.first(el, "material")
        if mat is not None:
            if "name" not in mat.attrs:
                msg = "visual material must have a name attribute"
                raise _InvalidError(msg)
            material_name = mat.attrs["name"]
            material = self.material(mat, only_name_ok=True)
        return Visual(
            geometry, origin, el.attrs.get("name"), material_name, material, self.source(el)
        )

    def collision(self, el: Element) -> Collision:
        origin = self.pose(self.first(el, "origin"), "collision")
        geometry = self.geometry(self.first(el, "geometry"))
        return Collision(geometry, origin, el.attrs.get("name"), self.source(el))

    # --- joints --------------------------------------------------------------------------------
    def joints(self, robot: Element) -> None:
        names: set[str] = set()
        for el in self.all(robot, "joint"):
            try:
                joint = self.joint(el)
            except _InvalidError as err:
                raise self.fatal(str(err), el) from None
            if joint.name in names:
                msg = f"joint '{joint.name}' is not unique"
                raise self.fatal(msg, el)
            names.add(joint.name)
            self.out.joints.append(joint)

    def joint(self, el: Element) -> Joint:
        name = el.attrs.get("name")
        if name is None:
            msg = "unnamed joint found"
            raise _InvalidError(msg)
        try:
            origin = self.pose(self.first(el, "origin"), f"joint [{name}]")
        except _InvalidError as err:
            msg = f"malformed origin for joint [{name}]: {err}"
            raise _InvalidError(msg) from None
        parent_el, child_el = self.first(el, "parent"), self.first(el, "child")
        parent = parent_el.attrs.get("link", "") if parent_el is not None else ""
        child = child_el.attrs.get("link", "") if child_el is not None else ""
        jtype = el.attrs.get("type")
        if jtype is None:
            msg = f"joint [{name}] has no type"
            raise _InvalidError(msg)
        if jtype not in JOINT_TYPES:
            msg = f"joint [{name}] has no known type [{jtype}] (expected {', '.join(JOINT_TYPES)})"
            raise _InvalidError(msg)
        joint_type: JointType = jtype
        axis: Vec3 = (1.0, 0.0, 0.0)
        if joint_type not in ("floating", "fixed"):
            axis_el = self.first(el, "axis")
            if axis_el is not None:
                axis = (0.0, 0.0, 0.0)
                if "xyz" in axis_el.attrs:
                    axis = _vec3(axis_el.attrs["xyz"], f"joint [{name}] axis")
        limit = None
        limit_el = self.first(el, "limit")
        if limit_el is not None:
            limit = self.limit(limit_el, name)
        elif joint_type in ("revolute", "prismatic"):
            msg = f"joint [{name}] is of type {joint_type} but does not specify limits"
            raise _InvalidError(msg)
        return Joint(
            name,
            joint_type,
            parent,
            child,
            origin,
            axis,
            limit,
            self.optional(el, "dynamics", name, self.dynamics),
            self.optional(el, "mimic", name, self.mimic),
            self.optional(el, "safety_controller", name, self.safety),
            self.optional(el, "calibration", name, self.calibration),
            self.source(el),
        )

    def optional(
        self, el: Element, tag: str, joint: str, parse: Callable[[dict[str, str], str], _T]
    ) -> _T | None:
        sub = self.first(el, tag)
        return None if sub is None else parse(sub.attrs, f"joint [{joint}] {tag}")

    @staticmethod
    def _opt(attrs: dict[str, str], key: str, what: str, default: float) -> float:
        return _number(attrs[key], f"{what} {key}") if key in attrs else default

    def limit(self, el: Element, joint: str) -> Limit:
        what = f"joint [{joint}] limit"
        a = el.attrs
        for key in ("effort", "velocity"):
            if key not in a:
                msg = f"{what}: no {key}"
                raise _InvalidError(msg)
        return Limit(
            _number(a["effort"], f"{what} effort"),
            _number(a["velocity"], f"{what} velocity"),
            self._opt(a, "lower", what, 0.0),
            self._opt(a, "upper", what, 0.0),
        )

    def dynamics(self, a: dict[str, str], what: str) -> Dynamics:
        if "damping" not in a and "friction" not in a:
            msg = f"{what}: specified with no damping and no friction"
            raise _InvalidError(msg)
        return Dynamics(self._opt(a, "damping", what, 0.0), self._opt(a, "friction", what, 0.0))

    def mimic(self, a: dict[str, str], what: str) -> Mimic:
        if "joint" not in a:
            msg = f"{what}: no joint to mimic"
            raise _InvalidError(msg)
        return Mimic(
            a["joint"], self._opt(a, "multiplier", what, 1.0), self._opt(a, "offset", what, 0.0)
        )

    def safety(self, a: dict[str, str], what: str) -> SafetyController:
        if "k_velocity" not in a:
            msg = f"{what}: no k_velocity"
            raise _InvalidError(msg)
        return SafetyController(
            _number(a["k_velocity"], f"{what} k_velocity"),
            self._opt(a, "k_position", what, 0.0),
            self._opt(a, "soft_lower_limit", what, 0.0),
            self._opt(a, "soft_upper_limit", what, 0.0),
        )

    def calibration(self, a: dict[str, str], what: str) -> Calibration:
        rising = _number(a["rising"], f"{what} rising") if "rising" in a else None
        falling = _number(a["falling"], f"{what} falling") if "falling" in a else None
        return Calibration(rising, falling)

    # --- the tree (as urdfdom builds it: joints by name, then links by name) -------------------
    def tree(self, robot: Element) -> None:
        links = {link.name for link in self.out.links}
        has_parent: set[str] = set()
        by_name = {j.name: j for j in self.out.joints}
        for name in sorted(by_name):
            joint = by_name[name]
            el = joint.source
            if not joint.parent or not joint.child:
                msg = f"joint [{name}] is missing a parent and/or child link specification"
                raise self.fatal(msg, el)
            if joint.child not in links:
                msg = f"child link [{joint.child}] of joint [{name}] not found"
                raise self.fatal(msg, el)
            if joint.parent not in links:
                msg = (
                    f"parent link [{joint.parent}] of joint [{name}] not found: every link a "
                    f'joint refers to must be defined (add <link name="{joint.parent}"/>)'
                )
                raise self.fatal(msg, el)
            has_parent.add(joint.child)
        roots = sorted(links - has_parent)
        if len(roots) > 1:
            msg = f"two root links found: [{roots[0]}] and [{roots[1]}]"
            raise self.fatal(msg, robot)
        if not roots:
            msg = "no root link found: the robot is not a tree (a cycle?)"
            raise self.fatal(msg, robot)

    # --- ROS extensions ------------------------------------------------------------------------
    def transmission(self, el: Element) -> None:
        name = el.attrs.get("name", "")
        legacy = "type" in el.attrs
        type_el = self.first(el, "type")
        ttype = el.attrs.get("type") or (_text(type_el).strip() if type_el is not None else "")
        joints = tuple(
            TransmissionJoint(
                j.attrs.get("name", ""),
                tuple(_text(h).strip() for h in self.all(j, "hardwareInterface")),
            )
            for j in self.all(el, "joint")
        )
        actuators = []
        for a in self.all(el, "actuator"):
            reduction_el = self.first(a, "mechanicalReduction") or self.first(
                el, "mechanicalReduction"
            )
            reduction = None
            if reduction_el is not None:
                try:
                    reduction = _number(_text(reduction_el).strip(), "mechanicalReduction")
                except _InvalidError as err:
                    severity: Literal["error", "warning"] = (
                        "error" if isinstance(err, _NonFiniteError) else "warning"
                    )
                    self.report(severity, f"transmission [{name}]: {err}", reduction_el)
            interfaces = tuple(_text(h).strip() for h in self.all(a, "hardwareInterface"))
            actuators.append(Actuator(a.attrs.get("name", ""), reduction, interfaces))
        if not name:
            self.report("warning", "transmission without a name", el)
        self.out.transmissions.append(
            Transmission(name, ttype, joints, tuple(actuators), legacy, self.source(el))
        )

    def data(self, el: Element) -> XmlData:
        return XmlData(
            el.tag,
            tuple(el.attrs.items()),
            _text(el),
            tuple(self.data(c) for c in el.elements()),
            self.source(el),
        )

    def gazebo(self, el: Element) -> GazeboExtension:
        props: list[tuple[str, str]] = []
        plugins: list[GazeboPlugin] = []
        sensors: list[XmlData] = []
        other: list[XmlData] = []
        for child in el.elements():
            if child.tag == "plugin":
                plugins.append(
                    GazeboPlugin(
                        child.attrs.get("name", ""),
                        child.attrs.get("filename", ""),
                        tuple(self.data(p) for p in child.elements()),
                        self.source(child),
                    )
                )
            elif child.tag == "sensor":
                sensors.append(self.data(child))
            elif child.first_element() is None and not child.attrs:
                props.append((child.tag, _text(child).strip()))
            else:
                other.append(self.data(child))
        return GazeboExtension(
            el.attrs.get("reference"),
            tuple(props),
            tuple(plugins),
            tuple(sensors),
            tuple(other),
            self.source(el),
        )
