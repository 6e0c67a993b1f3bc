"""Reading a ``.world`` (or a model ``.sdf``): the world element, its includes, its
``<state>``; the element families are read by the reader's bases."""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np

from belvedere.errors import SourceLocation
from belvedere.packages import PackageIndex
from belvedere.world._elements import child as _child
from belvedere.world._elements import floats as _floats
from belvedere.world._frames import FrameGraph
from belvedere.world._model import Light, SDFError, WorldModel, WorldModelEntry
from belvedere.world._paths import BUILTIN_MODELS, ModelPaths, model_sdf_file
from belvedere.world._poses import from_matrix, inverse, matrix
from belvedere.world._sdf._environment import EnvironmentReader
from belvedere.world._sdf._models import ModelReader
from belvedere.world._sdf._scope import _ModelRead, _pose_at
from belvedere.xmldom import Element, parse_file, parse_string, write_pretty

__all__ = ["empty_world", "read_world", "read_world_string"]

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


def _kept(el: Element) -> str:
    """An element as XML text; SDF 1.4's ``<gravity>`` inside ``<physics>`` left out (the
    world's own ``<gravity>`` is written in its place)."""
    copy = el.clone()
    for c in [c for c in copy.elements() if el.tag == "physics" and c.tag == "gravity"]:
        c.detach()
    return write_pretty(copy)


class _Reader(ModelReader, EnvironmentReader):
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
