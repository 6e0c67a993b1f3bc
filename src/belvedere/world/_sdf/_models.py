"""SDF models: their links, joints, frames and nested models in one frame graph; an
``<include>``'s overrides; the built-in ``ground_plane`` and ``sun``."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from belvedere.description.gazebo_materials import gazebo_material_colours
from belvedere.description.urdf import Pose, transform
from belvedere.world._elements import child as _child
from belvedere.world._elements import flag as _flag
from belvedere.world._elements import plugin as _plugin
from belvedere.world._frames import FrameGraph, Matrix4
from belvedere.world._model import (
    Attenuation,
    Light,
    Material,
    Plane,
    SDFError,
    Shape,
    Surface,
    WorldJoint,
    WorldLink,
    WorldModelEntry,
)
from belvedere.world._sdf._links import LinkReader
from belvedere.world._sdf._scope import _ModelRead, _pose_at
from belvedere.xmldom import Element

__all__ = ["ModelReader"]


class ModelReader(LinkReader):
    """Models, and the models ``<include>`` brings in."""

    if TYPE_CHECKING:

        def include(self, el: Element) -> _ModelRead | Light | None: ...

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
