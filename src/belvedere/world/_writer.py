"""Writing a :class:`WorldModel` as an SDF 1.6 ``.world``, as Gazebo classic saves one.

A model that came from the model path is an ``<include>`` of its ``model://`` URI (with its
``<name>``, ``<pose>`` and ``<static>``); any other is written out in full (links, inertials,
collisions, visuals, sensors, joints, plugins). Lights, physics and scene follow, the
elements the world kept as written (its ``<gui>`` camera, solver settings, plugins) as they
were, and, given a :class:`WorldState`, Gazebo's ``<state>`` block: the time, and where every
model and link is.
Numbers are written in full (the shortest text that reads back as the same double), poses
rounded to 1e-12.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from belvedere.description.urdf import (
    Box,
    Cylinder,
    GazeboPlugin,
    Inertial,
    Mesh,
    Pose,
    Sphere,
    xml_element,
)
from belvedere.fileio import write_file
from belvedere.world._model import (
    RGBA,
    Light,
    Material,
    Plane,
    Polyline,
    Shape,
    Surface,
    WorldGeometry,
    WorldJoint,
    WorldLink,
    WorldModel,
    WorldModelEntry,
)
from belvedere.world._poses import compose, matrix
from belvedere.xmldom import Element, Text, parse_string, write_pretty

__all__ = ["WorldState", "world_sdf", "write_world"]

SDF_VERSION = "1.6"


@dataclass(frozen=True, slots=True)
class WorldState:
    """When a world was saved: the header of Gazebo's ``<state>`` block (the poses come from
    the world's models)."""

    sim_time_ns: int
    wall_time_ns: int
    iterations: int
    real_time_ns: int | None = None
    """Wall-clock time the simulation has run (None: not written)."""


def write_world(path: str | os.PathLike[str], world: WorldModel, state: WorldState | None) -> Path:
    """Write ``world`` to ``path`` whole or not at all (a temporary file beside it, flushed
    to disk, renamed over it). Returns the file written.

    Raises:
        FileWriteError: nothing was changed (names the file and the reason).
    """
    return write_file(path, world_sdf(world, state))


class Courtesy:
    """Lets other threads run every ``period_s`` of work: a simulation saving its world runs
    on beside the save, and CPython runs one thread's Python at a time (a thread that asks
    for it waits up to 5 ms; a simulation stepping at 1 kHz asks often)."""

    def __init__(self, period_s: float = 0.001) -> None:
        self.period_s = period_s
        self.last = time.perf_counter()

    def __call__(self) -> None:
        now = time.perf_counter()
        if now - self.last >= self.period_s:
            time.sleep(0)
            self.last = time.perf_counter()


def world_sdf(world: WorldModel, state: WorldState | None = None) -> str:
    """``world`` as the text of an SDF 1.6 ``.world`` file (made a model at a time, letting
    other threads run in between: see :class:`Courtesy`)."""
    courtesy = Courtesy()
    out = [
        '<?xml version="1.0" ?>\n',
        f'<sdf version="{SDF_VERSION}">\n',
        f"  <world name={quoteattr(world.name)}>\n",
    ]
    out += [_indented(el, 2) for el in _settings(world)]
    for light in world.lights:
        out.append(_indented(_light(light), 2))
    for model in world.models:
        out.append(_indented(_include(model) if _included(model) else _model(model), 2))
        courtesy()
    if state is not None:
        out.append(f"    <state world_name={quoteattr(world.name)}>\n")
        for el in _state(world, state):
            out.append(_indented(el, 3))
            courtesy()
        out.append("    </state>\n")
    out.append("  </world>\n</sdf>\n")
    return "".join(out)


def _indented(el: Element, depth: int) -> str:
    pad = "  " * depth
    return "".join(pad + line for line in write_pretty(el).splitlines(keepends=True))


def _settings(world: WorldModel) -> list[Element]:
    """Gravity, physics and scene, then what the world kept as it wrote it."""
    kept = [
        parse_string(text, "<kept>", namespaces=False, keep_blank=False).root for text in world.kept
    ]
    tags = {el.tag for el in kept}
    holder = Element("world")
    _add(holder, "gravity", _nums(world.physics.gravity))
    if "physics" not in tags:
        physics = _add(holder, "physics", type="ode")
        _add(physics, "max_step_size", _num(world.physics.max_step_size))
        _add(physics, "real_time_factor", _num(world.physics.real_time_factor))
        _add(physics, "real_time_update_rate", _num(world.physics.real_time_update_rate))
    if "scene" not in tags:
        scene = _add(holder, "scene")
        _add(scene, "ambient", _nums(world.scene.ambient))
        _add(scene, "background", _nums(world.scene.background))
        _add(scene, "shadows", _flag(world.scene.shadows))
    return [*holder.elements(), *kept]


def _included(model: WorldModelEntry) -> bool:
    return model.uri is not None and model.uri.startswith("model://")


# --- numbers ------------------------------------------------------------------------------------
def _num(value: float) -> str:
    """The shortest text that reads back as the same double; ``1`` rather than ``1.0``."""
    value = float(value)
    if value == 0.0:
        return "0"  # no "-0"
    text = repr(value)
    return text[:-2] if text.endswith(".0") else text


def _nums(values: Iterable[float]) -> str:
    return " ".join(_num(v) for v in values)


POSE_DECIMALS = 12
"""Poses are written to a picometre and a picoradian: a simulation's rounding noise (``1e-17``
rad of yaw) drops out, nothing a reload would notice does."""


def _pose(pose: Pose) -> str:
    return _nums(round(v, POSE_DECIMALS) for v in (*pose.xyz, *pose.rpy))


def _flag(value: bool) -> str:
    return "1" if value else "0"


def _ns(ns: int) -> str:
    """Gazebo's time text: seconds and nanoseconds."""
    return f"{ns // 1_000_000_000} {ns % 1_000_000_000}"


def _add(parent: Element, tag: str, text: str | None = None, **attrs: str) -> Element:
    el = Element(tag, dict(attrs))
    if text is not None:
        el.append(Text(text))
    parent.append(el)
    return el


# --- models ---------------------------------------------------------------------------------------
def _include(model: WorldModelEntry) -> Element:
    el = Element("include")
    assert model.uri is not None
    _add(el, "uri", model.uri)
    _add(el, "name", model.name)
    _add(el, "pose", _pose(model.pose))
    _add(el, "static", _flag(model.static))
    return el


def _model(model: WorldModelEntry) -> Element:
    el = Element("model", {"name": model.name})
    _add(el, "static", _flag(model.static))
    _add(el, "pose", _pose(model.pose))
    for link in model.links:
        el.append(_link(link))
    for joint in model.joints:
        el.append(_joint(joint))
    for plugin in model.plugins:
        el.append(_plugin(plugin))
    return el


def _plugin(plugin: GazeboPlugin) -> Element:
    el = Element("plugin", {"name": plugin.name, "filename": plugin.filename})
    for param in plugin.params:
        el.append(xml_element(param))
    return el


def _link(link: WorldLink) -> Element:
    el = Element("link", {"name": link.name})
    _add(el, "pose", _pose(link.pose))
    if not link.gravity:
        _add(el, "gravity", "0")
    if link.kinematic:
        _add(el, "kinematic", "1")
    if link.inertial is not None:
        el.append(_inertial(link.inertial))
    for shape in link.collisions:
        el.append(_shape("collision", shape))
    for shape in link.visuals:
        el.append(_shape("visual", shape))
    for sensor in link.sensors:
        el.append(xml_element(sensor))
    return el


def _inertial(inertial: Inertial) -> Element:
    el = Element("inertial")
    _add(el, "pose", _pose(inertial.origin))
    _add(el, "mass", _num(inertial.mass))
    tensor = _add(el, "inertia")
    for tag in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"):
        _add(tensor, tag, _num(getattr(inertial, tag)))
    return el


def _shape(kind: str, shape: Shape) -> Element:
    el = Element(kind, {"name": shape.name})
    _add(el, "pose", _pose(shape.pose))
    el.append(_geometry(shape.geometry))
    if shape.surface is not None:
        el.append(_surface(shape.surface))
    material = shape.material
    if material is None and shape.rgba is not None:
        material = Material(shape.rgba, shape.rgba)
    if material is not None:
        el.append(_material(material))
    return el


def _geometry(geometry: WorldGeometry) -> Element:
    el = Element("geometry")
    if isinstance(geometry, Box):
        _add(_add(el, "box"), "size", _nums(geometry.size))
    elif isinstance(geometry, Cylinder):
        cylinder = _add(el, "cylinder")
        _add(cylinder, "radius", _num(geometry.radius))
        _add(cylinder, "length", _num(geometry.length))
    elif isinstance(geometry, Sphere):
        _add(_add(el, "sphere"), "radius", _num(geometry.radius))
    elif isinstance(geometry, Plane):
        plane = _add(el, "plane")
        _add(plane, "normal", _nums(geometry.normal))
        _add(plane, "size", _nums(geometry.size))
    elif isinstance(geometry, Polyline):
        polyline = _add(el, "polyline")
        for point in geometry.points:
            _add(polyline, "point", _nums(point))
        _add(polyline, "height", _num(geometry.height))
    else:
        mesh = _add(el, "mesh")
        _add(mesh, "uri", _file_uri(geometry))
        _add(mesh, "scale", _nums(geometry.scale))
    return el


def _file_uri(mesh: Mesh) -> str:
    """A mesh as Gazebo finds it from any directory: its absolute path."""
    name = mesh.filename
    if "://" in name:
        return name
    return "file://" + os.path.abspath(name)


def _surface(surface: Surface) -> Element:
    el = Element("surface")
    ode = _add(_add(el, "friction"), "ode")
    _add(ode, "mu", _num(surface.mu))
    _add(ode, "mu2", _num(surface.mu2))
    contact = {
        tag: value
        for tag, value in (
            ("kp", surface.kp),
            ("kd", surface.kd),
            ("max_vel", surface.max_vel),
            ("min_depth", surface.min_depth),
        )
        if value is not None
    }
    if contact:
        contact_ode = _add(_add(el, "contact"), "ode")
        for tag, value in contact.items():
            _add(contact_ode, tag, _num(value))
    return el


def _material(material: Material) -> Element:
    el = Element("material")
    colours: tuple[tuple[str, RGBA], ...] = (
        ("ambient", material.ambient),
        ("diffuse", material.diffuse),
        ("specular", material.specular),
        ("emissive", material.emissive),
    )
    for tag, rgba in colours:
        _add(el, tag, _nums(rgba))
    if material.shininess:
        _add(el, "shininess", _num(material.shininess))
    return el


def _joint(joint: WorldJoint) -> Element:
    """SDF 1.6: the pose in the child link's frame, the axis in the joint's own."""
    el = Element("joint", {"name": joint.name, "type": joint.type})
    _add(el, "parent", joint.parent)
    _add(el, "child", joint.child)
    _add(el, "pose", _pose(joint.pose))
    if joint.type in ("fixed", "ball"):
        return el
    axis_el = _add(el, "axis")
    rotation = matrix(joint.pose)[:3, :3]
    axis = rotation.T @ np.asarray(joint.axis, dtype=np.float64)
    _add(axis_el, "xyz", _nums(float(v) for v in axis))
    limits: list[tuple[str, float | None]] = []
    if joint.lower is not None and joint.upper is not None:
        limits += [("lower", joint.lower), ("upper", joint.upper)]
    limits += [("effort", joint.effort), ("velocity", joint.velocity)]
    if any(value is not None for _, value in limits):
        limit = _add(axis_el, "limit")
        for tag, value in limits:
            if value is not None:
                _add(limit, tag, _num(value))
    if joint.damping or joint.friction:
        dynamics = _add(axis_el, "dynamics")
        _add(dynamics, "damping", _num(joint.damping))
        _add(dynamics, "friction", _num(joint.friction))
    return el


# --- lights and state -------------------------------------------------------------------------
def _light(light: Light) -> Element:
    el = Element("light", {"name": light.name, "type": light.type})
    _add(el, "pose", _pose(light.pose))
    _add(el, "diffuse", _nums(light.diffuse))
    _add(el, "specular", _nums(light.specular))
    fall = light.attenuation
    attenuation = _add(el, "attenuation")
    for tag in ("range", "constant", "linear", "quadratic"):
        _add(attenuation, tag, _num(getattr(fall, tag)))
    _add(el, "direction", _nums(light.direction))
    _add(el, "cast_shadows", _flag(light.cast_shadows))
    if light.type == "spot":
        spot = _add(el, "spot")
        _add(spot, "inner_angle", _num(light.spot_inner_angle))
        _add(spot, "outer_angle", _num(light.spot_outer_angle))
        _add(spot, "falloff", _num(light.spot_falloff))
    return el


def _state(world: WorldModel, state: WorldState) -> Iterator[Element]:
    """What Gazebo's ``<state>`` holds: the time, and each model's and link's pose in the
    world."""
    holder = Element("state")
    _add(holder, "sim_time", _ns(state.sim_time_ns))
    if state.real_time_ns is not None:
        _add(holder, "real_time", _ns(state.real_time_ns))
    _add(holder, "wall_time", _ns(state.wall_time_ns))
    _add(holder, "iterations", str(state.iterations))
    yield from list(holder.elements())
    for model in world.models:
        model_el = Element("model", {"name": model.name})
        _add(model_el, "pose", _pose(model.pose))
        _add(model_el, "scale", "1 1 1")
        for link in model.links:
            link_el = _add(model_el, "link", name=link.name)
            _add(link_el, "pose", _pose(compose(model.pose, link.pose)))
        yield model_el
    for light in world.lights:
        light_el = Element("light", {"name": light.name})
        _add(light_el, "pose", _pose(light.pose))
        yield light_el
