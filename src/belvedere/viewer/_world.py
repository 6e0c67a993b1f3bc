"""A world's models in the scene: each model a frame (moved when the simulation says it
moved), each link's visuals under it. The ground plane is the grid; it is not drawn again."""

from __future__ import annotations

import logging
from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.description.meshes import load_mesh
from belvedere.description.urdf import Box, Cylinder, Mesh, Pose, Sphere
from belvedere.errors import BelvedereError
from belvedere.tf import Transform, quat_xyzw_from_rpy, wxyz_from_xyzw
from belvedere.world import Plane, Polyline, Shape, WorldModel, WorldModelEntry

__all__ = ["WorldDrawing"]

logger = logging.getLogger("belvedere.viewer")


def _wxyz(pose: Pose) -> tuple[float, float, float, float]:
    return wxyz_from_xyzw(quat_xyzw_from_rpy(*pose.rpy))


def _rgb(rgba: tuple[float, ...] | None) -> tuple[int, int, int]:
    r, g, b = rgba[:3] if rgba else (0.75, 0.75, 0.75)
    return (round(r * 255), round(g * 255), round(b * 255))


class WorldDrawing:
    """Scene nodes for a :class:`WorldModel` under ``root``."""

    def __init__(self, scene: Any, world: WorldModel, *, root: str = "/world") -> None:
        self.scene = scene
        self.root = root
        self.frames: dict[str, Any] = {}
        for model in world.models:
            self.add(model)

    def add(self, model: WorldModelEntry) -> None:
        """Draw ``model`` at its pose (a model inserted while the simulation runs)."""
        scene, root = self.scene, self.root
        frame = scene.add_frame(
            f"{root}/{model.name}",
            show_axes=False,
            position=model.pose.xyz,
            wxyz=_wxyz(model.pose),
        )
        self.frames[model.name] = frame
        for link in model.links:
            base = f"{root}/{model.name}/{link.name}"
            scene.add_frame(base, show_axes=False, position=link.pose.xyz, wxyz=_wxyz(link.pose))
            shapes = link.visuals or link.collisions
            for i, shape in enumerate(shapes):
                self._shape(scene, f"{base}/shape_{i}", shape)

    def remove(self, name: str) -> None:
        """Stop drawing model ``name`` (its links and shapes go with its frame)."""
        frame = self.frames.pop(name, None)
        if frame is not None:
            frame.remove()

    def _shape(self, scene: Any, name: str, shape: Shape) -> None:
        g = shape.geometry
        color = _rgb(shape.rgba)
        pose = {"position": shape.pose.xyz, "wxyz": _wxyz(shape.pose)}
        if isinstance(g, Box):
            scene.add_box(name, color=color, dimensions=g.size, **pose)
        elif isinstance(g, Cylinder):
            scene.add_cylinder(name, radius=g.radius, height=g.length, color=color, **pose)
        elif isinstance(g, Sphere):
            scene.add_icosphere(name, radius=g.radius, color=color, **pose)
        elif isinstance(g, Polyline):
            vertices, faces = _prism(g)
            scene.add_mesh_simple(name, vertices, faces, color=color, **pose)
        elif isinstance(g, Mesh):
            try:
                mesh = load_mesh(g.filename, scale=g.scale, requested_at=shape.source)
            except BelvedereError as err:
                logger.warning("%s", err.describe())
                return
            scene.add_mesh_simple(
                name,
                mesh.vertices.astype(np.float32),
                mesh.faces.astype(np.uint32),
                color=color,
                **pose,
            )
        elif isinstance(g, Plane):
            return  # the floor: the grid shows it

    def update(self, poses: Mapping[str, Transform]) -> None:
        """Move the models that moved (world-frame poses by model name)."""
        for name, t in poses.items():
            frame = self.frames.get(name)
            if frame is not None:
                frame.position = t.translation
                frame.wxyz = wxyz_from_xyzw(t.quat_xyzw)


def _prism(line: Polyline) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.uint32]]:
    """The polygon extruded to ``height``: sides as quads, caps as fans (convex or not,
    the fan is good enough for walls drawn by the building editor)."""
    n = len(line.points)
    bottom = [(x, y, 0.0) for x, y in line.points]
    top = [(x, y, line.height) for x, y in line.points]
    vertices = np.array(bottom + top, dtype=np.float32)
    faces: list[tuple[int, int, int]] = []
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, n + j), (i, n + j, n + i)]
    for i in range(1, n - 1):
        faces += [(0, i + 1, i), (n, n + i, n + i + 1)]
    return vertices, np.array(faces, dtype=np.uint32)
