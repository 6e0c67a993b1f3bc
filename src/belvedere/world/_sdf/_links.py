"""SDF links (inertials, collisions and visuals, their geometry) and joints, posed through
their model's frame graph."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from belvedere.description.urdf import Box, Cylinder, Inertial, Mesh, Pose, Sphere
from belvedere.world._elements import child as _child
from belvedere.world._elements import flag as _flag
from belvedere.world._elements import floats as _floats
from belvedere.world._elements import number as _number
from belvedere.world._elements import positive as _positive
from belvedere.world._elements import read_material, read_surface, xml_data
from belvedere.world._frames import FrameGraph
from belvedere.world._model import (
    Plane,
    Polyline,
    SDFError,
    Shape,
    WorldGeometry,
    WorldJoint,
    WorldLink,
)
from belvedere.world._sdf._scope import ElementReader, _pose_at, _rotate, _version
from belvedere.xmldom import Element

__all__ = ["LinkReader"]


class LinkReader(ElementReader):
    """A model's links and joints."""

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
