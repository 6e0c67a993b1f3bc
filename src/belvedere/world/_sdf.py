"""Reading SDF 1.4 to 1.9: ``.world`` files and ``model.sdf`` into a :class:`WorldModel`.

Handled: ``<physics>`` (and 1.4's gravity inside it), models (static or not) with links,
inertials, collisions, visuals, joints, nested models and frames; geometry box, cylinder,
sphere, plane, mesh, polyline; poses with ``degrees`` and quaternions, placed through each
scope's frame graph (:mod:`belvedere.world._frames`: SDF 1.7's ``relative_to``,
``attached_to``, ``canonical_link``, ``placement_frame``, ``expressed_in``; before 1.7 the
fixed rules and the ``frame`` attribute); ``<include>`` of ``model://`` (with ``<name>``,
``<pose>``, ``<static>``, ``<placement_frame>``); world ``<frame>``s; the ``<state>`` block
Gazebo writes when it saves a world; lights. What is not simulated (actors, populations,
heightmaps, world plugins) is a warning naming its line. A model's plugins and its links'
sensors are kept as written: a robot saved in the world runs them again.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from belvedere.description.gazebo_materials import gazebo_material_colours
from belvedere.description.urdf import Box, Cylinder, Inertial, Mesh, Pose, Sphere, transform
from belvedere.errors import SourceLocation
from belvedere.packages import PackageIndex
from belvedere.world._elements import child as _child
from belvedere.world._elements import flag as _flag
from belvedere.world._elements import floats as _floats
from belvedere.world._elements import number as _number
from belvedere.world._elements import plugin as _plugin
from belvedere.world._elements import positive as _positive
from belvedere.world._elements import read_colour, read_material, read_surface, xml_data
from belvedere.world._frames import FrameGraph, Matrix4
from belvedere.world._model import (
    Attenuation,
    Light,
    Material,
    Physics,
    Plane,
    Polyline,
    Scene,
    SDFError,
    Shape,
    Surface,
    WorldFrame,
    WorldGeometry,
    WorldJoint,
    WorldLink,
    WorldModel,
    WorldModelEntry,
)
from belvedere.world._paths import BUILTIN_MODELS, ModelPaths, model_sdf_file
from belvedere.world._poses import from_matrix, inverse, matrix, quat_xyzw_to_rpy
from belvedere.xmldom import Element, parse_file, parse_string, write_pretty

__all__ = ["SDFError", "empty_world", "read_world", "read_world_string"]

EMPTY_WORLD = """<sdf version="1.6"><world name="default">
  <include><uri>model://ground_plane</uri></include>
  <include><uri>model://sun</uri></include>
</world></sdf>"""

_IGNORED_WORLD = {"scene", "gui", "spherical_coordinates", "magnetic_field", "atmosphere", "wind"}
_IGNORED_WORLD |= {"audio", "gravity", "physics", "model", "include", "light", "state", "plugin"}
_UNSUPPORTED = {"actor", "population", "road"}
_KEPT = {"gui", "physics", "scene", "spherical_coordinates", "atmosphere", "magnetic_field"}
_KEPT |= {"wind", "audio", "plugin"}
"""World elements a saved world keeps as written (what the simulation reads of them is
written from the model)."""


def read_world(
    path: str | Path,
    *,
    packages: PackageIndex | None = None,
    model_paths: ModelPaths | None = None,
) -> WorldModel:
    """Read a ``.world`` (or a model ``.sdf``, which becomes a world holding that model)."""
    doc = parse_file(path, namespaces=False, keep_blank=False)
    return _Reader(_paths(packages, model_paths), str(path)).world(doc.root)


def read_world_string(
    text: str,
    path: str = "<string>",
    *,
    packages: PackageIndex | None = None,
    model_paths: ModelPaths | None = None,
) -> WorldModel:
    doc = parse_string(text, path, namespaces=False, keep_blank=False)
    return _Reader(_paths(packages, model_paths), path).world(doc.root)


def empty_world(*, model_paths: ModelPaths | None = None) -> WorldModel:
    """gazebo_ros's ``empty.world``: a ground plane and the sun (built in unless installed)."""
    return read_world_string(EMPTY_WORLD, "<empty world>", model_paths=model_paths)


def _paths(packages: PackageIndex | None, model_paths: ModelPaths | None) -> ModelPaths:
    return model_paths or ModelPaths.from_environment(packages=packages)


def _version(text: str) -> tuple[int, int]:
    parts = [int(p) for p in text.strip().split(".")[:2] if p.isdigit()]
    major, minor = [*parts, 0, 0][:2]
    return major, minor


def _kept(el: Element) -> str:
    """An element as XML text; SDF 1.4's ``<gravity>`` inside ``<physics>`` left out (the
    world's own ``<gravity>`` is written in its place)."""
    copy = el.clone()
    for c in [c for c in copy.elements() if el.tag == "physics" and c.tag == "gravity"]:
        c.detach()
    return write_pretty(copy)


def _pose_at(el: Element) -> SourceLocation | None:
    """Where an element's pose is written (its ``<pose>``, else the element)."""
    pose = _child(el, "pose")
    return (pose if pose is not None else el).loc


def _rotate(rotation: Matrix4, v: tuple[float, float, float]) -> tuple[float, float, float]:
    r = rotation[:3, :3] @ np.asarray(v, dtype=np.float64)
    return (float(r[0]), float(r[1]), float(r[2]))


@dataclass(slots=True)
class _ModelRead:
    """A model read on its own, not yet placed in the scope that holds it."""

    entry: WorldModelEntry
    graph: FrameGraph
    pose: Matrix4
    """The model frame's pose in ``relative_to`` (a placement frame already applied)."""
    relative_to: str | None
    """None: the frame of the scope that holds the model."""
    pose_at: SourceLocation | None


class _Reader:
    def __init__(self, model_paths: ModelPaths, path: str) -> None:
        self.paths = model_paths
        self.path = path
        self.version = "1.6"
        self.warnings: list[str] = []
        self.including: list[str] = []

    def warn(self, where: SourceLocation | None, text: str) -> None:
        self.warnings.append(f"{where or self.path}: warning: {text}")

    @property
    def modern(self) -> bool:
        """SDF 1.7 frame semantics (``relative_to``, ``attached_to``, one namespace)."""
        return _version(self.version) >= (1, 7)

    # --- poses ----------------------------------------------------------------------------------
    def pose(self, parent: Element) -> tuple[Pose, str | None]:
        """The ``<pose>`` of ``parent`` as written and the frame it names (None: the default
        for this kind of element)."""
        el = _child(parent, "pose")
        if el is None:
            return Pose(), None
        relative_to = el.attrs.get("relative_to") or None
        legacy_frame = el.attrs.get("frame") or None
        if legacy_frame is not None and relative_to is None:
            if self.modern:
                self.warn(
                    el.loc,
                    f"<pose frame={legacy_frame!r}> is SDF 1.5/1.6; SDF {self.version} ignores it "
                    "(as Gazebo does): write relative_to",
                )
            else:
                relative_to = legacy_frame
        degrees = el.attrs.get("degrees", "false").strip().lower() in ("1", "true")
        values = _floats(el) or (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # <pose relative_to="f"/>
        if el.attrs.get("rotation_format") == "quat_xyzw" or len(values) == 7:
            if len(values) != 7:
                msg = "a quat_xyzw <pose> needs 7 numbers: x y z qx qy qz qw"
                raise SDFError(msg, el.loc)
            rpy = quat_xyzw_to_rpy(*values[3:])
        elif len(values) == 6:
            r, p, y = values[3:6]
            rpy = (math.radians(r), math.radians(p), math.radians(y)) if degrees else (r, p, y)
        else:
            msg = f"<pose> expects 6 numbers (x y z roll pitch yaw), got {len(values)}"
            raise SDFError(msg, el.loc)
        return Pose((values[0], values[1], values[2]), (rpy[0], rpy[1], rpy[2])), relative_to

    def name(self, el: Element, kind: str) -> str:
        """An element's ``name``: present, and (SDF 1.7+) not one SDF reserves."""
        name = el.attrs.get("name", "")
        if not name:
            msg = f"<{el.tag}> needs a name"
            raise SDFError(msg, el.loc)
        if self.modern and (name == "world" or (name.startswith("__") and name.endswith("__"))):
            msg = f"{kind} name {name!r} is reserved in SDF {self.version}"
            raise SDFError(
                msg,
                el.loc,
                hint="'world' and names that start and end with '__' name frames "
                "SDF defines itself",
            )
        if _version(self.version) >= (1, 8) and "::" in name:
            msg = f"{kind} name {name!r} contains '::', which SDF {self.version} keeps for scopes"
            raise SDFError(msg, el.loc)
        return name

    # --- world ----------------------------------------------------------------------------------
    def world(self, root: Element) -> WorldModel:
        if root.tag != "sdf":
            msg = f"expected an <sdf> document, found <{root.tag}>"
            raise SDFError(msg, root.loc, hint="Gazebo classic worlds start with <sdf version=…>")
        self.version = root.attrs.get("version", "1.6")
        world_el = _child(root, "world")
        if world_el is None:
            alone = [self.model(m) for m in root.elements() if m.tag == "model"]
            if not alone:
                msg = "no <world> or <model> in this SDF file"
                raise SDFError(msg, root.loc)
            graph = FrameGraph("this file", "world", legacy=not self.modern)
            models = self._place_models(graph, alone)
            return WorldModel(
                models=tuple(models),
                path=self.path,
                sdf_version=self.version,
                warnings=tuple(self.warnings),
            )
        world_name = world_el.attrs.get("name", "default")
        graph = FrameGraph(f"world {world_name!r}", "world", legacy=not self.modern)
        reads: list[_ModelRead | Element] = []  # models and frames, in the file's order
        lights: list[tuple[Light, str | None, SourceLocation | None]] = []
        for el in world_el.elements():
            if el.tag == "model":
                reads.append(self.model(el))
            elif el.tag == "include":
                included = self.include(el)
                if isinstance(included, Light):
                    lights.append((included, None, el.loc))
                elif included is not None:
                    reads.append(included)
            elif el.tag == "light":
                lights.append((self.light(el), self.pose(el)[1], _pose_at(el)))
            elif el.tag == "frame":
                reads.append(el)
            elif el.tag in _UNSUPPORTED:
                self.warn(el.loc, f"<{el.tag}> is not simulated; ignored")
            elif el.tag == "plugin":
                name = el.attrs.get("filename", "?")
                if "gazebo_ros_api" not in name and "gazebo_ros_state" not in name:
                    self.warn(el.loc, f"world plugin {name!r} is not supported; ignored")
        models = self._place_models(graph, reads)
        placed_lights = [
            light
            if rel is None
            else replace(
                light,
                pose=from_matrix(
                    graph.resolve(light.pose, rel, asked_by=f"pose of light {light.name!r}", at=at)
                ),
            )
            for light, rel, at in lights
        ]
        models = self.apply_state(world_el, models)
        return WorldModel(
            name=world_name,
            physics=self.physics(world_el),
            models=tuple(models),
            lights=tuple(placed_lights),
            frames=self._frames(graph),
            scene=self.scene(_child(world_el, "scene")),
            path=self.path,
            sdf_version=self.version,
            warnings=tuple(self.warnings),
            kept=tuple(_kept(el) for el in world_el.elements() if el.tag in _KEPT),
        )

    def _place_models(
        self, graph: FrameGraph, items: list[_ModelRead | Element] | list[_ModelRead]
    ) -> list[WorldModelEntry]:
        """Put the world's models and frames into its frame graph; each model's pose in the
        world."""
        reads = [r for r in items if isinstance(r, _ModelRead)]
        self._unique([r.entry for r in reads])
        for read in items:
            if not isinstance(read, _ModelRead):
                self.frame(graph, read, scope_frame="world")
                continue
            graph.add_nested(
                read.entry.name,
                read.graph,
                read.pose,
                relative_to=read.relative_to or "world",
                static=read.entry.static,
                source=read.pose_at,
            )
        graph.check()
        return [replace(r.entry, pose=graph.pose(r.entry.name)) for r in reads]

    def frame(self, graph: FrameGraph, el: Element, *, scope_frame: str) -> None:
        """An explicit ``<frame>``: attached to ``attached_to`` (default: the scope's frame),
        posed relative to ``relative_to`` (default: what it is attached to)."""
        name = self.name(el, "frame")
        attached = (el.attrs.get("attached_to") if self.modern else None) or scope_frame
        pose, rel = self.pose(el)
        graph.add(
            name,
            "frame",
            pose,
            relative_to=rel or attached,
            attached_to=attached,
            source=_pose_at(el) if rel else el.loc,
        )

    def _frames(self, graph: FrameGraph) -> tuple[WorldFrame, ...]:
        return tuple(
            WorldFrame(name, graph.pose(name), graph.body(name), graph.frames[name].source)
            for name in graph.names("frame")
        )

    def scene(self, el: Element | None) -> Scene:
        """``<scene>``: ambient light, background colour, shadows (off unless asked for)."""
        if el is None:
            return Scene()
        default = Scene()
        return Scene(
            ambient=read_colour(_child(el, "ambient"), default.ambient),
            background=read_colour(_child(el, "background"), default.background),
            shadows=_flag(el, "shadows", default.shadows),
        )

    def physics(self, world_el: Element) -> Physics:
        physics_el = _child(world_el, "physics")
        gravity = (0.0, 0.0, -9.8)
        for holder in (physics_el, world_el):  # 1.4 keeps gravity inside <physics>
            g = _child(holder, "gravity") if holder is not None else None
            if g is not None:
                x, y, z = _floats(g, 3)
                gravity = (x, y, z)
        if physics_el is None:
            return Physics(gravity=gravity)
        step = _positive(physics_el, "max_step_size", 0.001)
        return Physics(
            max_step_size=step,
            real_time_update_rate=_number(physics_el, "real_time_update_rate", 1000.0),
            real_time_factor=_number(physics_el, "real_time_factor", 1.0),
            gravity=gravity,
        )

    def light(self, el: Element) -> Light:
        pose, _ = self.pose(el)
        direction = _child(el, "direction")
        v = _floats(direction, 3) if direction is not None else (-0.5, 0.1, -0.9)
        attenuation = _child(el, "attenuation")
        fall = Attenuation()
        if attenuation is not None:
            fall = Attenuation(
                range=_number(attenuation, "range", fall.range),
                constant=_number(attenuation, "constant", fall.constant),
                linear=_number(attenuation, "linear", fall.linear),
                quadratic=_number(attenuation, "quadratic", fall.quadratic),
            )
        spot = _child(el, "spot")
        return Light(
            name=el.attrs.get("name", "light"),
            type=el.attrs.get("type", "point"),
            pose=pose,
            diffuse=read_colour(_child(el, "diffuse"), (0.8, 0.8, 0.8, 1.0)),
            direction=(v[0], v[1], v[2]),
            cast_shadows=_flag(el, "cast_shadows", False),
            specular=read_colour(_child(el, "specular"), (0.1, 0.1, 0.1, 1.0)),
            attenuation=fall,
            spot_inner_angle=_number(spot, "inner_angle", 0.0) if spot is not None else 0.0,
            spot_outer_angle=_number(spot, "outer_angle", 0.0) if spot is not None else 0.0,
            spot_falloff=_number(spot, "falloff", 0.0) if spot is not None else 0.0,
            source=el.loc,
        )

    # --- includes ---------------------------------------------------------------------------------
    def include(self, el: Element) -> _ModelRead | Light | None:
        uri_el = _child(el, "uri")
        if uri_el is None:
            msg = "<include> needs a <uri>"
            raise SDFError(msg, el.loc)
        uri = uri_el.text_content().strip()
        name = uri.removeprefix("model://").strip("/")
        if not uri.startswith("model://"):
            path = Path(uri.removeprefix("file://"))
            if not path.is_absolute():
                path = Path(self.path).parent / path
            directory: Path | None = path if os.path.isdir(path) else None
        else:
            directory = self.paths.find(name)
        if directory is None:
            if name in BUILTIN_MODELS:
                builtin = self.builtin(name, el)
                if isinstance(builtin, Light):
                    return builtin
                read = _ModelRead(builtin, self._one_link_graph(builtin), np.eye(4), None, el.loc)
                return self._included(el, read, uri)
            msg = f"model {uri!r} not found (searched: {self.paths.searched()})"
            raise SDFError(
                msg,
                uri_el.loc,
                hint="put the model under ~/.gazebo/models or a GAZEBO_MODEL_PATH directory; "
                "belvedere never downloads models",
            )
        sdf_file = model_sdf_file(directory)
        key = str(sdf_file.resolve())
        if key in self.including:
            msg = f"include cycle: {uri} includes itself"
            raise SDFError(msg, uri_el.loc)
        if not os.path.isfile(sdf_file):
            msg = f"model {uri!r}: {sdf_file} does not exist"
            raise SDFError(msg, uri_el.loc)
        self.including.append(key)
        try:
            doc = parse_file(sdf_file, namespaces=False, keep_blank=False)
            inner = _Reader(self.paths, str(sdf_file))
            inner.including = self.including
            inner.version = doc.root.attrs.get("version", self.version)
            model_el = _child(doc.root, "model")
            light_el = _child(doc.root, "light")
            if model_el is None and light_el is not None:
                return inner.light(light_el)
            if model_el is None:
                msg = f"{sdf_file} has no <model>"
                raise SDFError(msg, doc.root.loc)
            read = inner.model(model_el)
            self.warnings += inner.warnings
        finally:
            self.including.pop()
        return self._included(el, read, uri)

    def _included(self, el: Element, read: _ModelRead, uri: str) -> _ModelRead:
        """An ``<include>``'s overrides: its ``<name>``, ``<static>``, and its ``<pose>``,
        which replaces the model's own (in this file's scope, so its ``relative_to`` names a
        frame here), placing the model's ``<placement_frame>`` if it names one."""
        name_el = _child(el, "name")
        entry = replace(
            read.entry,
            name=name_el.text_content().strip() if name_el is not None else read.entry.name,
            static=_flag(el, "static", read.entry.static),
            uri=uri,
            source=el.loc,
        )
        if entry.name != read.entry.name:
            read.graph.scope = f"model {entry.name!r}"
        if _child(el, "pose") is None:
            return replace(read, entry=entry, relative_to=None)
        pose, rel = self.pose(el)
        matrix = transform(pose)
        placement_el = _child(el, "placement_frame")
        if placement_el is not None:
            matrix = self._placed(matrix, read.graph, placement_el.text_content().strip(), el)
        return _ModelRead(entry, read.graph, matrix, rel, _pose_at(el))

    def _placed(self, pose: Matrix4, graph: FrameGraph, placement: str, el: Element) -> Matrix4:
        """``pose`` gives where frame ``placement`` of the model goes: the model frame's pose."""
        model_from_placement = graph.in_root(
            placement, asked_by=f"{graph.scope}'s placement_frame", at=el.loc
        )
        result: Matrix4 = pose @ np.linalg.inv(model_from_placement)
        return result

    def _one_link_graph(self, entry: WorldModelEntry) -> FrameGraph:
        graph = FrameGraph(f"model {entry.name!r}", "__model__")
        for link in entry.links:
            graph.add(
                link.name,
                "link",
                link.pose,
                relative_to="__model__",
                attached_to=None,
                source=link.source,
            )
        graph.attach_root(None if entry.static else entry.links[0].name)
        return graph

    def builtin(self, name: str, el: Element) -> WorldModelEntry | Light:
        if name == "sun":
            return Light(  # Gazebo's model://sun
                name="sun",
                type="directional",
                pose=Pose((0.0, 0.0, 10.0)),
                cast_shadows=True,
                specular=(0.2, 0.2, 0.2, 1.0),
                attenuation=Attenuation(1000.0, 0.9, 0.01, 0.001),
                source=el.loc,
            )
        plane = Shape(
            "collision",
            Plane((0.0, 0.0, 1.0), (100.0, 100.0)),
            surface=Surface(mu=100.0, mu2=50.0),
            source=el.loc,
        )
        grey = gazebo_material_colours("Gazebo/Grey")
        assert grey is not None
        visual = Shape(
            "visual",
            Plane((0.0, 0.0, 1.0), (100.0, 100.0)),
            rgba=grey.diffuse,
            material=Material(grey.ambient, grey.diffuse, grey.specular, shininess=grey.shininess),
        )
        link = WorldLink("link", collisions=(plane,), visuals=(visual,), source=el.loc)
        return WorldModelEntry(
            name="ground_plane",
            static=True,
            links=(link,),
            uri="model://ground_plane",
            source=el.loc,
            canonical_link="link",
        )

    # --- models -----------------------------------------------------------------------------------
    def model(self, el: Element) -> _ModelRead:
        """A ``<model>`` and its frame graph: links posed in the model frame, shapes in their
        link's frame, joints in their child link's frame; nested models flattened into
        ``nested::link`` and ``nested::joint``."""
        name = self.name(el, "model")
        static = _flag(el, "static", False)
        graph = FrameGraph(f"model {name!r}", "__model__", legacy=not self.modern)
        parts: list[tuple[Element, _ModelRead | None]] = []  # own links, nested models in order
        joint_els: list[Element] = []
        nested: list[_ModelRead] = []
        plugin_els: list[Element] = []
        for child in el.elements():
            if child.tag == "link":
                link_name = self.name(child, "link")
                pose, rel = self.pose(child)
                graph.add(
                    link_name,
                    "link",
                    pose,
                    relative_to=rel or "__model__",
                    attached_to=None,
                    source=_pose_at(child),
                )
                parts.append((child, None))
            elif child.tag == "joint":
                joint_name = self.name(child, "joint")
                child_el = _child(child, "child")
                pose, rel = self.pose(child)
                child_link = child_el.text_content().strip() if child_el is not None else ""
                graph.add(
                    joint_name,
                    "joint",
                    pose,
                    relative_to=rel or child_link,
                    attached_to=child_link,
                    source=_pose_at(child),
                )
                joint_els.append(child)
            elif child.tag == "frame":
                self.frame(graph, child, scope_frame="__model__")
            elif child.tag in ("model", "include"):
                inner = self.model(child) if child.tag == "model" else self.include(child)
                if isinstance(inner, Light):
                    self.warn(child.loc, "a light included in a model is not simulated; ignored")
                elif inner is not None:
                    graph.add_nested(
                        inner.entry.name,
                        inner.graph,
                        inner.pose,
                        relative_to=inner.relative_to or "__model__",
                        static=inner.entry.static,
                        source=inner.pose_at,
                    )
                    nested.append(inner)
                    parts.append((child, inner))
            elif child.tag == "plugin":
                plugin_els.append(child)  # a saved robot's: the simulation runs it
        canonical = self._canonical(el, graph, nested)
        graph.attach_root(None if static else canonical)
        for joint_el in joint_els:
            self._joint_links(joint_el, graph)
        graph.check()
        links: list[WorldLink] = []
        joints: list[WorldJoint] = []
        for part_el, inner in parts:
            if inner is None:
                links.append(self.link(part_el, graph))
                continue
            prefix = f"{inner.entry.name}::"
            links += [
                replace(lk, name=prefix + lk.name, pose=graph.pose(prefix + lk.name))
                for lk in inner.entry.links
            ]
            joints += [
                replace(
                    j,
                    name=prefix + j.name,
                    parent=j.parent if j.parent == "world" else prefix + j.parent,
                    child=prefix + j.child,
                )
                for j in inner.entry.joints
            ]
        joints = [self.joint(j, graph) for j in joint_els] + joints
        pose, rel = self.pose(el)
        matrix = transform(pose)
        placement = el.attrs.get("placement_frame")
        if placement:
            matrix = self._placed(matrix, graph, placement, el)
        entry = WorldModelEntry(
            name=name,
            static=static,
            links=tuple(links),
            joints=tuple(joints),
            source=el.loc,
            frames=self._frames(graph),
            canonical_link=canonical,
            plugins=tuple(_plugin(p) for p in plugin_els),
        )
        return _ModelRead(entry, graph, matrix, rel, _pose_at(el))

    def _canonical(self, el: Element, graph: FrameGraph, nested: list[_ModelRead]) -> str | None:
        """The link the model frame is attached to: ``canonical_link``, else the first link,
        else the first nested model's canonical link."""
        named = el.attrs.get("canonical_link") if self.modern else None
        links = graph.names("link")
        if named:
            if graph.kind(named) != "link":
                msg = (
                    f"model {el.attrs.get('name')!r}: canonical_link {named!r} is not a link of it"
                )
                raise SDFError(msg, el.loc, hint=f"links: {', '.join(links) or 'none'}")
            return named
        for name, frame in graph.frames.items():
            if frame.kind == "link" and "::" not in name:
                return name
        for inner in nested:
            if inner.entry.canonical_link is not None:
                return f"{inner.entry.name}::{inner.entry.canonical_link}"
        return None

    def _joint_links(self, el: Element, graph: FrameGraph) -> None:
        name = el.attrs.get("name", "")
        links = graph.names("link")
        for role in ("parent", "child"):
            role_el = _child(el, role)
            if role_el is None:
                msg = f"joint {name!r} needs <parent> and <child>"
                raise SDFError(msg, el.loc)
            link = role_el.text_content().strip()
            if graph.kind(link) == "link" or (role == "parent" and link == "world"):
                continue
            msg = f"joint {name!r}: {role} link {link!r} is not a link of this model"
            raise SDFError(msg, role_el.loc, hint=f"links: {', '.join(sorted(links))}")

    def link(self, el: Element, graph: FrameGraph) -> WorldLink:
        name = el.attrs["name"]
        collisions = tuple(
            s
            for c in el.elements()
            if c.tag == "collision"
            if (s := self.shape(c, graph, name)) is not None
        )
        visuals = tuple(
            s
            for c in el.elements()
            if c.tag == "visual"
            if (s := self.shape(c, graph, name)) is not None
        )
        return WorldLink(
            name=name,
            pose=graph.pose(name),
            inertial=self.inertial(_child(el, "inertial"), graph, name),
            collisions=collisions,
            visuals=visuals,
            gravity=_flag(el, "gravity", True),
            kinematic=_flag(el, "kinematic", False),
            source=el.loc,
            sensors=tuple(xml_data(c) for c in el.elements() if c.tag == "sensor"),
        )

    def in_link(self, el: Element, graph: FrameGraph, link: str, what: str) -> Pose:
        """The pose of a link's part (collision, visual, inertial) in the link's frame: written
        relative to the link, or (SDF 1.7) to any frame of the model."""
        pose, rel = self.pose(el)
        if rel is None or rel == link:
            return pose
        placed = graph.resolve(pose, rel, asked_by=f"pose of {what}", at=_pose_at(el))
        return graph.between(link, placed)

    def inertial(self, el: Element | None, graph: FrameGraph, link: str) -> Inertial | None:
        if el is None:
            return None
        pose = self.in_link(el, graph, link, f"the inertial of link {link!r}")
        inertia = _child(el, "inertia")

        def value(tag: str, default: float) -> float:
            return _number(inertia, tag, default) if inertia is not None else default

        mass = _positive(el, "mass", 1.0)
        return Inertial(
            mass=mass,
            ixx=value("ixx", 1.0),
            ixy=value("ixy", 0.0),
            ixz=value("ixz", 0.0),
            iyy=value("iyy", 1.0),
            iyz=value("iyz", 0.0),
            izz=value("izz", 1.0),
            origin=pose,
        )

    def shape(self, el: Element, graph: FrameGraph, link: str) -> Shape | None:
        geometry_el = _child(el, "geometry")
        if geometry_el is None:
            msg = f"<{el.tag}> needs a <geometry>"
            raise SDFError(msg, el.loc)
        geometry = self.geometry(geometry_el)
        if geometry is None:
            return None
        name = el.attrs.get("name", el.tag)
        material = read_material(_child(el, "material")) if el.tag == "visual" else None
        return Shape(
            name=name,
            geometry=geometry,
            pose=self.in_link(el, graph, link, f"{el.tag} {name!r}"),
            surface=read_surface(_child(el, "surface")) if el.tag == "collision" else None,
            rgba=material.diffuse if material is not None else None,
            material=material,
            source=el.loc,
        )

    def geometry(self, el: Element) -> WorldGeometry | None:
        kind = el.first_element()
        if kind is None:
            msg = "<geometry> is empty"
            raise SDFError(msg, el.loc)
        tag = kind.tag
        get: Callable[[str, float], float] = lambda t, d: _number(kind, t, d)  # noqa: E731
        if tag == "box":
            size_el = _child(kind, "size")
            x, y, z = _floats(size_el, 3) if size_el is not None else (1.0, 1.0, 1.0)
            return Box((x, y, z))
        if tag == "cylinder":
            return Cylinder(get("radius", 0.5), get("length", 1.0))
        if tag == "sphere":
            return Sphere(get("radius", 0.5))
        if tag == "plane":
            normal = _child(kind, "normal")
            size = _child(kind, "size")
            n = _floats(normal, 3) if normal is not None else (0.0, 0.0, 1.0)
            s = _floats(size, 2) if size is not None else (100.0, 100.0)
            return Plane((n[0], n[1], n[2]), (s[0], s[1]))
        if tag == "mesh":
            uri_el = _child(kind, "uri")
            if uri_el is None:
                msg = "<mesh> needs a <uri>"
                raise SDFError(msg, kind.loc)
            scale_el = _child(kind, "scale")
            sx, sy, sz = _floats(scale_el, 3) if scale_el is not None else (1.0, 1.0, 1.0)
            return Mesh(str(self.mesh_path(uri_el)), (sx, sy, sz))
        if tag == "polyline":
            points = tuple(
                (p[0], p[1])
                for pt in kind.elements()
                if pt.tag == "point"
                for p in [_floats(pt, 2)]
            )
            if len(points) < 3:
                msg = "<polyline> needs at least 3 <point>s"
                raise SDFError(msg, kind.loc)
            return Polyline(points, get("height", 1.0))
        self.warn(kind.loc, f"<{tag}> geometry is not simulated; shape ignored")
        return None

    def mesh_path(self, uri_el: Element) -> Path:
        uri = uri_el.text_content().strip()
        if uri.startswith("model://"):
            name, _, rest = uri.removeprefix("model://").partition("/")
            directory = self.paths.find(name)
            if directory is None:
                msg = f"mesh {uri!r}: model {name!r} not found (searched: {self.paths.searched()})"
                raise SDFError(msg, uri_el.loc)
            return directory / rest
        if uri.startswith("file://"):
            return Path(uri.removeprefix("file://"))
        path = Path(uri)
        return path if path.is_absolute() else Path(self.path).parent / path

    def joint(self, el: Element, graph: FrameGraph) -> WorldJoint:
        """A joint posed in its child link's frame, its axis expressed there too."""
        name = el.attrs.get("name", "")
        kind = el.attrs.get("type", "")
        parent_el, child_el = _child(el, "parent"), _child(el, "child")
        assert parent_el is not None  # checked with the graph
        assert child_el is not None
        parent, child = parent_el.text_content().strip(), child_el.text_content().strip()
        raw, rel = self.pose(el)
        model_from_joint = graph.resolve(
            raw, rel or child, asked_by=f"pose of joint {name!r}", at=_pose_at(el)
        )
        child_from_model = np.linalg.inv(graph.in_root(child))
        axis_el = _child(el, "axis")
        axis = (0.0, 0.0, 1.0)
        lower = upper = effort = velocity = None
        damping = friction = 0.0
        if axis_el is not None:
            xyz_el = _child(axis_el, "xyz")
            if xyz_el is not None:
                x, y, z = _floats(xyz_el, 3)
                frame = self._axis_frame(axis_el, xyz_el)
                expressed = (
                    model_from_joint
                    if frame is None
                    else graph.in_root(frame, asked_by=f"the axis of joint {name!r}", at=xyz_el.loc)
                )
                axis = _rotate(child_from_model @ expressed, (x, y, z))
            limit = _child(axis_el, "limit")
            if limit is not None and kind in ("revolute", "prismatic"):
                lower, upper = _number(limit, "lower", -1e16), _number(limit, "upper", 1e16)
            if limit is not None:
                given = {c.tag for c in limit.elements()}
                effort = _number(limit, "effort", -1.0) if "effort" in given else None
                velocity = _number(limit, "velocity", -1.0) if "velocity" in given else None
            dynamics = _child(axis_el, "dynamics")
            if dynamics is not None:
                damping = _number(dynamics, "damping", 0.0)
                friction = _number(dynamics, "friction", 0.0)
        pose = graph.between(child, model_from_joint)
        return WorldJoint(
            name,
            kind,
            parent,
            child,
            pose,
            axis,
            lower,
            upper,
            damping,
            friction,
            el.loc,
            effort=effort,
            velocity=velocity,
        )

    def _axis_frame(self, axis_el: Element, xyz_el: Element) -> str | None:
        """The frame a joint axis is written in (None: the joint's own). SDF < 1.5: the model
        frame; 1.5-1.6: the joint frame unless ``use_parent_model_frame``; 1.7+:
        ``expressed_in`` (default the joint frame)."""
        if self.modern:
            return xyz_el.attrs.get("expressed_in") or None
        if _version(self.version) < (1, 5) or _flag(axis_el, "use_parent_model_frame", False):
            return "__model__"
        return None

    # --- whole-world passes -----------------------------------------------------------------------
    def apply_state(
        self, world_el: Element, models: list[WorldModelEntry]
    ) -> list[WorldModelEntry]:
        """A saved world's ``<state>`` holds where everything was: it wins over the poses."""
        state = _child(world_el, "state")
        if state is None:
            return models
        by_name = {m.name: i for i, m in enumerate(models)}
        out = list(models)
        for el in state.elements():
            if el.tag != "model" or el.attrs.get("name") not in by_name:
                continue
            i = by_name[el.attrs["name"]]
            model = out[i]
            if _child(el, "pose") is not None:
                model = replace(model, pose=self.pose(el)[0])
            scale = _child(el, "scale")
            if scale is not None and any(abs(s - 1.0) > 1e-9 for s in _floats(scale, 3)):
                self.warn(scale.loc, f"model {model.name!r} is scaled in <state>; scale ignored")
            model_from_world = matrix(inverse(model.pose))
            links = list(model.links)
            for link_el in (c for c in el.elements() if c.tag == "link"):
                j = next(
                    (k for k, lk in enumerate(links) if lk.name == link_el.attrs.get("name")), None
                )
                if j is None or _child(link_el, "pose") is None:
                    continue
                world_pose = matrix(self.pose(link_el)[0])
                rel = from_matrix(model_from_world @ world_pose)
                links[j] = replace(links[j], pose=rel)
            out[i] = replace(model, links=tuple(links))
        return out

    def _unique(self, models: list[WorldModelEntry]) -> None:
        seen: dict[str, WorldModelEntry] = {}
        for m in models:
            if m.name in seen:
                msg = f"two models are named {m.name!r} (the first at {seen[m.name].source})"
                raise SDFError(msg, m.source, hint="give the <include> a <name> of its own")
            seen[m.name] = m
