"""``RobotModel`` → URDF text."""

from __future__ import annotations

from collections.abc import Iterable

from belvedere.description.urdf._model import (
    Box,
    Collision,
    Cylinder,
    GazeboExtension,
    Geometry,
    Inertial,
    Joint,
    Link,
    Material,
    Mesh,
    Pose,
    Sphere,
    Transmission,
    Visual,
    XmlData,
)
from belvedere.xmldom import Document, Element, Text, write_pretty

__all__ = ["write_urdf", "xml_element"]


def _num(x: float) -> str:
    """Shortest text that reads back as the same float (``1`` rather than ``1.0``)."""
    if x.is_integer() and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


def _nums(values: Iterable[float]) -> str:
    return " ".join(_num(v) for v in values)


def _el(tag: str, attrs: dict[str, str] | None = None, *children: Element | None) -> Element:
    el = Element(tag, attrs or {})
    for c in children:
        if c is not None:
            el.append(c)
    return el


def _text_el(tag: str, text: str) -> Element:
    el = Element(tag)
    el.append(Text(text))
    return el


def _origin(pose: Pose) -> Element | None:
    if pose == Pose():
        return None
    return _el("origin", {"xyz": _nums(pose.xyz), "rpy": _nums(pose.rpy)})


def _geometry(g: Geometry) -> Element:
    if isinstance(g, Box):
        shape = _el("box", {"size": _nums(g.size)})
    elif isinstance(g, Cylinder):
        shape = _el("cylinder", {"radius": _num(g.radius), "length": _num(g.length)})
    elif isinstance(g, Sphere):
        shape = _el("sphere", {"radius": _num(g.radius)})
    else:
        assert isinstance(g, Mesh)
        attrs = {"filename": g.filename}
        if g.scale != (1.0, 1.0, 1.0):
            attrs["scale"] = _nums(g.scale)
        shape = _el("mesh", attrs)
    return _el("geometry", None, shape)


def _material(m: Material) -> Element:
    el = _el("material", {"name": m.name})
    if m.rgba is not None:
        el.append(_el("color", {"rgba": _nums(m.rgba)}))
    if m.texture is not None:
        el.append(_el("texture", {"filename": m.texture}))
    return el


def _visual(v: Visual) -> Element:
    el = _el("visual", {"name": v.name} if v.name is not None else None)
    origin = _origin(v.origin)
    if origin is not None:
        el.append(origin)
    el.append(_geometry(v.geometry))
    if v.material is not None:
        el.append(_material(v.material))
    elif v.material_name is not None:
        el.append(_el("material", {"name": v.material_name}))
    return el


def _collision(c: Collision) -> Element:
    el = _el("collision", {"name": c.name} if c.name is not None else None)
    origin = _origin(c.origin)
    if origin is not None:
        el.append(origin)
    el.append(_geometry(c.geometry))
    return el


def _inertial(i: Inertial) -> Element:
    inertia = {
        "ixx": _num(i.ixx),
        "ixy": _num(i.ixy),
        "ixz": _num(i.ixz),
        "iyy": _num(i.iyy),
        "iyz": _num(i.iyz),
        "izz": _num(i.izz),
    }
    return _el(
        "inertial",
        None,
        _origin(i.origin),
        _el("mass", {"value": _num(i.mass)}),
        _el("inertia", inertia),
    )


def _link(link: Link) -> Element:
    el = _el("link", {"name": link.name})
    if link.inertial is not None:
        el.append(_inertial(link.inertial))
    for v in link.visuals:
        el.append(_visual(v))
    for c in link.collisions:
        el.append(_collision(c))
    return el


def _joint(j: Joint) -> Element:
    el = _el(
        "joint",
        {"name": j.name, "type": j.type},
        _origin(j.origin),
        _el("parent", {"link": j.parent}),
        _el("child", {"link": j.child}),
    )
    if j.type not in ("fixed", "floating"):
        el.append(_el("axis", {"xyz": _nums(j.axis)}))
    if j.limit is not None:
        lim = j.limit
        el.append(
            _el(
                "limit",
                {
                    "lower": _num(lim.lower),
                    "upper": _num(lim.upper),
                    "effort": _num(lim.effort),
                    "velocity": _num(lim.velocity),
                },
            )
        )
    if j.dynamics is not None:
        d = j.dynamics
        el.append(_el("dynamics", {"damping": _num(d.damping), "friction": _num(d.friction)}))
    if j.mimic is not None:
        m = j.mimic
        el.append(
            _el(
                "mimic",
                {"joint": m.joint, "multiplier": _num(m.multiplier), "offset": _num(m.offset)},
            )
        )
    if j.safety_controller is not None:
        s = j.safety_controller
        el.append(
            _el(
                "safety_controller",
                {
                    "k_velocity": _num(s.k_velocity),
                    "k_position": _num(s.k_position),
                    "soft_lower_limit": _num(s.soft_lower_limit),
                    "soft_upper_limit": _num(s.soft_upper_limit),
                },
            )
        )
    if j.calibration is not None:
        attrs = {}
        if j.calibration.rising is not None:
            attrs["rising"] = _num(j.calibration.rising)
        if j.calibration.falling is not None:
            attrs["falling"] = _num(j.calibration.falling)
        el.append(_el("calibration", attrs))
    return el


def _transmission(t: Transmission) -> Element:
    if t.legacy:
        el = _el("transmission", {"name": t.name, "type": t.type})
        for j in t.joints:
            el.append(_el("joint", {"name": j.name}))
        for a in t.actuators:
            el.append(_el("actuator", {"name": a.name}))
        reduction = next(
            (a.mechanical_reduction for a in t.actuators if a.mechanical_reduction is not None),
            None,
        )
        if reduction is not None:
            el.append(_text_el("mechanicalReduction", _num(reduction)))
        return el
    el = _el("transmission", {"name": t.name}, _text_el("type", t.type))
    for j in t.joints:
        joint = _el("joint", {"name": j.name})
        for h in j.hardware_interfaces:
            joint.append(_text_el("hardwareInterface", h))
        el.append(joint)
    for a in t.actuators:
        act = _el("actuator", {"name": a.name})
        for h in a.hardware_interfaces:
            act.append(_text_el("hardwareInterface", h))
        if a.mechanical_reduction is not None:
            act.append(_text_el("mechanicalReduction", _num(a.mechanical_reduction)))
        el.append(act)
    return el


def xml_element(d: XmlData) -> Element:
    """XML kept as data (a sensor, a plugin's parameter) as an element again."""
    el = _el(d.tag, dict(d.attrs))
    if d.text.strip() and not d.children:
        el.append(Text(d.text))
    for c in d.children:
        el.append(xml_element(c))
    return el


def _gazebo(g: GazeboExtension) -> Element:
    el = _el("gazebo", {"reference": g.reference} if g.reference is not None else None)
    for tag, value in g.properties:
        el.append(_text_el(tag, value) if value else _el(tag))
    for p in g.plugins:
        plugin = _el("plugin", {"name": p.name, "filename": p.filename})
        for param in p.params:
            plugin.append(xml_element(param))
        el.append(plugin)
    for d in (*g.sensors, *g.other):
        el.append(xml_element(d))
    return el


def write_urdf(
    name: str,
    *,
    materials: Iterable[Material],
    links: Iterable[Link],
    joints: Iterable[Joint],
    transmissions: Iterable[Transmission],
    gazebo: Iterable[GazeboExtension],
) -> str:
    """URDF text for a robot: its name and its parts, written in this order (a
    :class:`RobotModel` hands over its own; see ``RobotModel.to_urdf``)."""
    doc = Document("<urdf>")
    robot = _el("robot", {"name": name})
    doc.append(robot)
    for m in materials:
        robot.append(_material(m))
    for link in links:
        robot.append(_link(link))
    for j in joints:
        robot.append(_joint(j))
    for t in transmissions:
        robot.append(_transmission(t))
    for g in gazebo:
        robot.append(_gazebo(g))
    return write_pretty(doc)
