"""Drawing a RobotModel in a viser scene: one frame per link, its visuals (and collisions)."""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from belvedere.description.gazebo_materials import gazebo_material_rgba
from belvedere.description.meshes import load_mesh, resolve_mesh_path
from belvedere.description.urdf import (
    Box,
    Cylinder,
    Geometry,
    Material,
    Mesh,
    Pose,
    RobotModel,
    Sphere,
)
from belvedere.errors import BelvedereError, ParseError, SourceLocation
from belvedere.packages import PackageIndex
from belvedere.tf import quat_xyzw_from_rpy, wxyz_from_xyzw

__all__ = ["MeshAccessError", "RobotDrawing", "allowed_mesh_path"]

logger = logging.getLogger("belvedere.viewer")


class MeshAccessError(ParseError):
    """A mesh path outside every package root the model may read from."""


def allowed_mesh_path(
    filename: str, *, model_path: str | None, packages: PackageIndex, at: SourceLocation | None
) -> Path:
    """Resolve a mesh reference and refuse anything outside the resolved package roots (and
    the model's own directory): no ``..`` escapes, no arbitrary absolute paths."""
    path = resolve_mesh_path(
        filename, relative_to=model_path, packages=packages, requested_at=at
    ).resolve()
    roots = [p.resolve() for p in packages.packages().values()]
    if model_path is not None:
        roots.append(Path(model_path).resolve().parent)
    if not any(path.is_relative_to(root) for root in roots):
        msg = f"mesh {filename!r} resolves to {path}, outside the package roots; refused"
        raise MeshAccessError(msg, at)
    return path


@dataclass
class _LinkDrawing:
    frame: Any
    visuals: list[Any] = field(default_factory=list)
    collisions: list[Any] = field(default_factory=list)


def _wxyz(pose: Pose) -> tuple[float, float, float, float]:
    x, y, z, w = quat_xyzw_from_rpy(*pose.rpy)
    return (w, x, y, z)


def _rgb(rgba: tuple[float, ...] | None) -> tuple[int, int, int]:
    if rgba is None:
        return (200, 200, 200)
    return (round(rgba[0] * 255), round(rgba[1] * 255), round(rgba[2] * 255))


class RobotDrawing:
    """The robot's links as viser scene nodes under ``root`` (e.g. ``/robot``)."""

    def __init__(
        self,
        scene: Any,
        model: RobotModel,
        *,
        root: str = "/robot",
        packages: PackageIndex | None = None,
    ) -> None:
        self.model = model
        self.root = root
        self.packages = packages or PackageIndex.from_environment(near=model.path)
        materials = {m.name: m for m in model.materials}
        self.links: dict[str, _LinkDrawing] = {}
        for link in model.links:
            # shown once placed (a link nothing places is not drawn at the origin)
            frame = scene.add_frame(f"{root}/{link.name}", show_axes=False, visible=False)
            drawing = _LinkDrawing(frame)
            gazebo = next(
                (
                    g.property("material")
                    for g in model.gazebo_for(link.name)
                    if g.property("material")
                ),
                None,
            )
            for i, visual in enumerate(link.visuals):
                material = (
                    visual.material
                    if visual.material and visual.material.rgba
                    else materials.get(visual.material_name or "")
                )
                color = _rgb(self._color(material, gazebo))
                handle = self._shape(
                    scene,
                    f"{root}/{link.name}/visual_{i}",
                    visual.geometry,
                    visual.origin,
                    color,
                    visual.source.best,
                    opacity=None,
                )
                if handle is not None:
                    drawing.visuals.append(handle)
            for i, collision in enumerate(link.collisions):
                handle = self._shape(
                    scene,
                    f"{root}/{link.name}/collision_{i}",
                    collision.geometry,
                    collision.origin,
                    (255, 120, 0),
                    collision.source.best,
                    opacity=0.5,
                )
                if handle is not None:
                    handle.visible = False
                    drawing.collisions.append(handle)
            self.links[link.name] = drawing

    @staticmethod
    def _color(material: Material | None, gazebo: str | None) -> tuple[float, ...] | None:
        if material is not None and material.rgba is not None:
            return material.rgba
        if gazebo is not None:
            return gazebo_material_rgba(gazebo)
        return None

    def _shape(
        self,
        scene: Any,
        name: str,
        geometry: Geometry,
        origin: Pose,
        color: tuple[int, int, int],
        at: SourceLocation | None,
        *,
        opacity: float | None,
    ) -> Any:
        pose = {"position": origin.xyz, "wxyz": _wxyz(origin)}
        if isinstance(geometry, Box):
            return scene.add_box(
                name, color=color, dimensions=geometry.size, opacity=opacity, **pose
            )
        if isinstance(geometry, Cylinder):
            return scene.add_cylinder(
                name,
                radius=geometry.radius,
                height=geometry.length,
                color=color,
                opacity=opacity,
                **pose,
            )
        if isinstance(geometry, Sphere):
            return scene.add_icosphere(
                name, radius=geometry.radius, color=color, opacity=opacity, **pose
            )
        assert isinstance(geometry, Mesh)
        try:
            path = allowed_mesh_path(
                geometry.filename, model_path=self.model.path, packages=self.packages, at=at
            )
            mesh = load_mesh(path, scale=geometry.scale, requested_at=at)
        except BelvedereError as err:  # MeshError, MeshAccessError, a missing package
            logger.warning("%s", err.describe())
            return None
        if mesh.face_colors is not None:
            color = tuple(int(c) for c in np.round(mesh.face_colors[0, :3] * 255))  # type: ignore[assignment]
        return scene.add_mesh_simple(
            name,
            mesh.vertices.astype(np.float32),
            mesh.faces.astype(np.uint32),
            color=color,
            opacity=opacity,
            **pose,
        )

    def show(self, *, visual: bool, collision: bool) -> None:
        """rviz's Visual Enabled and Collision Enabled."""
        for d in self.links.values():
            for h in d.collisions:
                h.visible = collision
            for h in d.visuals:
                h.visible = visual

    def set_alpha(self, alpha: float) -> None:
        """The visuals' opacity (rviz's Alpha; collisions stay half transparent)."""
        for d in self.links.values():
            for h in d.visuals:
                h.opacity = None if alpha >= 1.0 else max(0.0, alpha)

    def remove(self) -> None:
        for d in self.links.values():
            for h in (*d.visuals, *d.collisions):
                h.remove()
            d.frame.remove()
        self.links.clear()

    def set_link_pose(
        self,
        link: str,
        position: tuple[float, float, float],
        quat_xyzw: tuple[float, float, float, float],
    ) -> None:
        d = self.links.get(link)
        if d is not None:
            d.frame.position = position
            d.frame.wxyz = wxyz_from_xyzw(quat_xyzw)
            d.frame.visible = True
