"""Mesh files (STL, OBJ, Collada .dae) as triangle meshes, through trimesh.

``package://`` and relative paths resolve like ROS; ``scale`` is applied, and Collada's
``<unit meter=…>`` and ``<up_axis>`` are honoured. Loaded meshes are cached by path and
modification time. A missing or unreadable mesh is an error naming the file:line that
referred to it; a texture or material file a mesh refers to that cannot be found is one
warning per missing file (the mesh loads without it), never a traceback.

Only regular files are read: a mesh of at most :data:`~belvedere.bounded.MESH_FILE_BYTES`,
the textures and material files it refers to of at most
:data:`~belvedere.bounded.IMAGE_FILE_BYTES`, and a texture only if its header gives at most
:data:`~belvedere.bounded.IMAGE_PIXELS` pixels; anything else is an error naming the mesh,
the file and why, at the line that referred to the mesh.
"""

from __future__ import annotations

import contextlib
import functools
import io
import logging
import os
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Final
from urllib.parse import unquote

import numpy as np
import numpy.typing as npt

from belvedere.bounded import (
    IMAGE_FILE_BYTES,
    IMAGE_PIXELS,
    MESH_FILE_BYTES,
    LimitError,
    check_pixels,
    open_regular,
    read_regular,
)
from belvedere.errors import ParseError, SourceLocation
from belvedere.packages import PackageIndex

__all__ = ["MeshError", "TriangleMesh", "load_mesh", "resolve_mesh_path"]

_SUFFIXES: Final = {".stl": "stl", ".obj": "obj", ".dae": "dae"}

logger = logging.getLogger("belvedere.meshes")

_missing_reported: set[str] = set()
"""Missing files already warned about."""


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
    try:  # trimesh opens and reads what it is given: a regular file of a sane size only
        open_regular(file, limit=MESH_FILE_BYTES, what="mesh", name=f"{file}{where}").close()
    except LimitError as err:
        raise MeshError(err.message, requested_at) from None
    try:
        mesh = _read(file, kind, requested_at)
    except MeshError:
        raise
    except Exception as err:  # noqa: BLE001 (trimesh and its readers raise many kinds)
        msg = f"cannot read mesh {file}{where}: {err}"
        raise MeshError(msg, requested_at) from None
    vertices = mesh.vertices * np.asarray(scale, dtype=float)
    result = TriangleMesh(vertices, mesh.faces, mesh.face_colors, file)
    _cache[key] = result
    return result


class _QuietTracebacks(logging.Filter):
    """trimesh logs a texture it cannot read with its traceback: keep the line, drop the
    traceback, and make it a debug message (our resolver warns about missing files)."""

    def filter(self, record: logging.LogRecord) -> bool:
        if record.exc_info:
            record.exc_info = None
            record.exc_text = None
            record.levelno, record.levelname = logging.DEBUG, "DEBUG"
        return True


@contextlib.contextmanager
def _quiet_trimesh() -> Iterator[None]:
    quiet = _QuietTracebacks()
    trimesh_logger = logging.getLogger("trimesh")
    trimesh_logger.addFilter(quiet)
    try:
        yield
    finally:
        trimesh_logger.removeFilter(quiet)


@functools.cache
def _blank_png() -> bytes:
    """A 1x1 white PNG: what a missing texture reads as."""
    from PIL import Image

    out = io.BytesIO()
    Image.new("RGBA", (1, 1), (255, 255, 255, 255)).save(out, format="PNG")
    return out.getvalue()


class _RefusedError(Exception):
    """A file a mesh refers to that is not read (see :func:`_resolver`)."""


def _resolver(file: Path) -> Any:
    """trimesh's resolver for the files a mesh refers to (textures, .mtl), relative to the
    mesh: a missing one is one warning per file, and reads as a blank image.

    Only a regular file of a sane size is read, and an image only if its header gives at
    most :data:`~belvedere.bounded.IMAGE_PIXELS`; a refused file reads as a blank image too,
    and is kept in the resolver's ``refused`` (trimesh catches what a resolver raises), for
    :func:`_read` to raise once trimesh is done."""
    from trimesh.resolvers import FilePathResolver

    class Resolver(FilePathResolver):
        refused: LimitError | None = None

        def get(self, name: str) -> bytes:
            try:
                data: bytes = self._read(name)
            except _RefusedError:
                return _blank_png()
            except (OSError, ValueError):
                _report_missing(file, name)
                return b"" if name.lower().endswith(".mtl") else _blank_png()
            return data

        def _read(self, name: str) -> bytes:
            """The file ``name`` as trimesh's resolver finds it (the name, without a leading
            slash, or its last part under the mesh's directory), read within the caps."""
            for candidate in (name.strip(), name.strip().lstrip("/"), os.path.split(name)[-1]):
                try:
                    path = self.absolute(candidate)
                except ValueError:
                    continue
                if os.path.lexists(path):
                    return self._bounded(path, name)
            return bytes(super().get(name))  # raises: not found, or outside the mesh's tree

        def _bounded(self, path: Path, name: str) -> bytes:
            material = name.lower().endswith(".mtl")
            what = "material file" if material else "texture"
            try:
                data = read_regular(path, limit=IMAGE_FILE_BYTES, what=what, name=name)
                if not material:
                    _check_image(data, f"{what} {name}")
            except LimitError as err:
                if self.refused is None:
                    self.refused = err
                raise _RefusedError from None
            return data

    return Resolver(str(file))


def _check_image(data: bytes, what: str) -> None:
    """Refuse an image whose header gives more than IMAGE_PIXELS (anything Pillow does not
    take for an image passes: trimesh says what it makes of it)."""
    from PIL import Image, UnidentifiedImageError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            with Image.open(io.BytesIO(data)) as img:
                size = img.size
    except Image.DecompressionBombError:
        size = (IMAGE_PIXELS + 1, 1)  # past Pillow's own limit, so far past ours
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError):
        return
    check_pixels(*size, what=what)


def _missing_path(file: Path, name: str) -> Path:
    local = unquote(name.removeprefix("file://"))
    return Path(local) if os.path.isabs(local) else file.parent / local


def _report_missing(file: Path, name: str) -> None:
    """One warning per missing file, however many meshes refer to it."""
    key = os.path.normpath(_missing_path(file, name))
    if key not in _missing_reported:
        _missing_reported.add(key)
        logger.warning(
            "%s: warning: %r, which this mesh refers to, is not found (%s); the mesh is "
            "used without it",
            file,
            name,
            key,
        )


def _referenced_files(file: Path, kind: str) -> list[str]:
    """The image and material files a .dae or .obj names (as written)."""
    names: list[str] = []
    if kind == "dae":
        from belvedere.xmldom import parse_file

        try:
            root = parse_file(file, namespaces=False).root
        except ParseError:
            return names
        stack = [root]
        while stack:
            el = stack.pop()
            stack.extend(el.elements())
            if el.tag.endswith("image"):
                for child in el.elements():
                    if child.tag.endswith("init_from") and child.text_content().strip():
                        names.append(child.text_content().strip())
    elif kind == "obj":
        with contextlib.suppress(LimitError):
            text = read_regular(file, limit=MESH_FILE_BYTES).decode(errors="replace")
            for line in text.splitlines():
                words = line.split()
                if len(words) > 1 and words[0] == "mtllib":
                    names.append(" ".join(words[1:]))
        for mtl in list(names):
            with contextlib.suppress(LimitError):
                text = read_regular(file.parent / mtl).decode(errors="replace")
                for line in text.splitlines():
                    words = line.split()
                    is_map = words and (words[0].startswith("map_") or words[0] in _MTL_MAPS)
                    if is_map and len(words) > 1:
                        names.append(words[-1])
    return names


_MTL_MAPS: Final = {"bump", "disp", "decal", "refl", "norm"}


def _check_references(file: Path, kind: str) -> None:
    """One warning for each texture or material file the mesh names that is not there."""
    for name in _referenced_files(file, kind):
        if not _missing_path(file, name).exists():  # there but no file: the resolver says
            _report_missing(file, name)


def _read(file: Path, kind: str, requested_at: SourceLocation | None = None) -> TriangleMesh:
    import trimesh  # heavy: only where meshes are read

    _check_references(file, kind)

    resolver = _resolver(file)
    with _quiet_trimesh():
        loaded: Any = trimesh.load(
            str(file), file_type=kind, force="scene", process=False, resolver=resolver
        )
    if resolver.refused is not None:
        msg = f"mesh file {file}: {resolver.refused.message}"
        raise MeshError(msg, requested_at)
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
