"""Mesh files (STL, OBJ, Collada .dae) as triangle meshes, through trimesh.

``package://`` and relative paths resolve like ROS; ``scale`` is applied, and Collada's
``<unit meter=…>`` and ``<up_axis>`` are honoured. Loaded meshes are cached by path and
modification time. A missing or unreadable mesh is an error naming the file:line that
referred to it.
"""

from __future__ import annotations

import contextlib
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Final

import numpy as np
import numpy.typing as npt

from belvedere.errors import ParseError, SourceLocation
from belvedere.packages import PackageIndex

__all__ = ["MeshError", "TriangleMesh", "load_mesh", "resolve_mesh_path"]

_SUFFIXES: Final = {".stl": "stl", ".obj": "obj", ".dae": "dae"}


class MeshError(ParseError):
    """A mesh that cannot be found or read."""


@dataclass(frozen=True, eq=False)
class TriangleMesh:
    """Triangles in metres, in the mesh's own frame (scale and Collada units applied)."""

    vertices: npt.NDArray[np.float64]
    """(N, 3) vertex positions."""
    faces: npt.NDArray[np.int64]
    """(M, 3) vertex indices of each triangle."""
    face_colors: npt.NDArray[np.float64] | None = None
    """(M, 4) RGBA in [0, 1] per triangle, when the file gives colours (materials)."""
    path: Path = field(default=Path())

    @property
    def bounds(self) -> npt.NDArray[np.float64]:
        """(2, 3): minimum and maximum corner."""
        return np.stack([self.vertices.min(axis=0), self.vertices.max(axis=0)])


def resolve_mesh_path(
    filename: str,
    *,
    relative_to: str | os.PathLike[str] | None = None,
    packages: PackageIndex | None = None,
    requested_at: SourceLocation | None = None,
) -> Path:
    """The file a URDF ``<mesh filename=…>`` names: ``package://pkg/…``, ``file://…``, an
    absolute path, or a path relative to the directory of ``relative_to`` (the URDF)."""
    if filename.startswith("package://"):
        index = packages or PackageIndex.from_environment(
            near=os.fspath(relative_to) if relative_to is not None else None
        )
        return index.resolve_uri(filename, requested_at=requested_at)
    if filename.startswith("file://"):
        return Path(filename[len("file://") :])
    path = Path(filename)
    if not path.is_absolute() and relative_to is not None:
        path = Path(relative_to).parent / path
    return path


_cache: dict[tuple[Path, int, tuple[float, float, float]], TriangleMesh] = {}


def load_mesh(
    path: str | os.PathLike[str],
    *,
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0),
    requested_at: SourceLocation | None = None,
) -> TriangleMesh:
    """Load a mesh file (cached by path, modification time and scale)."""
    file = Path(path)
    where = f" (referenced at {requested_at})" if requested_at else ""
    try:
        stat = file.stat()
    except OSError:
        msg = f"mesh file {file} not found{where}"
        raise MeshError(msg, requested_at) from None
    kind = _SUFFIXES.get(file.suffix.lower())
    if kind is None:
        msg = f"mesh file {file}: unsupported format {file.suffix!r} (use .stl, .obj or .dae)"
        raise MeshError(msg, requested_at)
    key = (file.resolve(), stat.st_mtime_ns, scale)
    cached = _cache.get(key)
    if cached is not None:
        return cached
    try:
        mesh = _read(file, kind)
    except MeshError:
        raise
    except Exception as err:  # noqa: BLE001 (trimesh and its readers raise many kinds)
        msg = f"cannot read mesh {file}{where}: {err}"
        raise MeshError(msg, requested_at) from None
    vertices = mesh.vertices * np.asarray(scale, dtype=float)
    result = TriangleMesh(vertices, mesh.faces, mesh.face_colors, file)
    _cache[key] = result
    return result


def _read(file: Path, kind: str) -> TriangleMesh:
    import trimesh  # heavy: only where meshes are read

    loaded: Any = trimesh.load(str(file), file_type=kind, force="scene", process=False)
    geometries = list(loaded.dump()) if hasattr(loaded, "dump") else [loaded]
    if not geometries:
        msg = f"mesh file {file} holds no triangles"
        raise MeshError(msg)
    vertices: list[npt.NDArray[np.float64]] = []
    faces: list[npt.NDArray[np.int64]] = []
    colors: list[npt.NDArray[np.float64]] = []
    has_colors = False
    offset = 0
    for g in geometries:
        if not hasattr(g, "faces") or len(g.faces) == 0:
            continue
        vertices.append(np.asarray(g.vertices, dtype=float))
        faces.append(np.asarray(g.faces, dtype=np.int64) + offset)
        offset += len(g.vertices)
        face_colors = _face_colors(g)
        has_colors = has_colors or face_colors is not None
        colors.append(
            face_colors if face_colors is not None else np.ones((len(g.faces), 4), dtype=float)
        )
    if not faces:
        msg = f"mesh file {file} holds no triangles"
        raise MeshError(msg)
    all_vertices = np.concatenate(vertices)
    if kind == "dae":
        unit, up = _collada_frame(file)
        all_vertices = (all_vertices * unit) @ _UP_TO_Z[up].T
    return TriangleMesh(
        all_vertices,
        np.concatenate(faces),
        np.concatenate(colors) if has_colors else None,
        file,
    )


def _face_colors(geometry: Any) -> npt.NDArray[np.float64] | None:
    visual = getattr(geometry, "visual", None)
    if visual is None:
        return None
    try:
        if visual.kind == "face" or visual.kind == "vertex":
            colors = np.asarray(visual.face_colors, dtype=float) / 255.0
            return colors
        material = getattr(visual, "material", None)
        if material is not None:
            rgba = getattr(material, "main_color", None)
            if rgba is None and hasattr(material, "diffuse"):
                rgba = material.diffuse
            if rgba is not None:
                c = np.asarray(rgba, dtype=float) / 255.0
                return np.tile(c, (len(geometry.faces), 1))
    except (AttributeError, ValueError, TypeError):
        return None
    return None


# Rotations that bring a Collada file's up axis to +Z (ROS's convention), as assimp does.
_UP_TO_Z: Final = {
    "Z_UP": np.eye(3),
    "Y_UP": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),
    "X_UP": np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]),
}


def _collada_frame(file: Path) -> tuple[float, str]:
    """Collada's ``<unit meter=…>`` and ``<up_axis>`` (trimesh applies neither)."""
    from belvedere.xmldom import parse_file

    unit, up = 1.0, "Y_UP"  # Collada's defaults
    try:
        root = parse_file(file, namespaces=False).root
    except ParseError:
        return unit, up
    asset = next((el for el in root.elements() if el.tag.endswith("asset")), None)
    if asset is None:
        return unit, up
    for el in asset.elements():
        if el.tag.endswith("unit") and "meter" in el.attrs:
            with contextlib.suppress(ValueError):
                unit = float(el.attrs["meter"])
        elif el.tag.endswith("up_axis"):
            text = el.text_content().strip().upper()
            if text in _UP_TO_Z:
                up = text
    return unit, up
