"""The model library: every model on the model path, as Gazebo's Insert tab lists it.

Each directory of :class:`ModelPaths` is scanned for model directories (a ``model.config``,
or an ``.sdf`` file that shows one was meant); each becomes a :class:`LibraryModel` named
by its ``model.config``. A model that cannot be read (no ``model.config``, a broken config
or SDF) is listed with its error, naming file and line: one bad download never hides the
others. A name found in two directories is the first one, as ``model://`` resolves it.
"""

from __future__ import annotations

import logging
import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from xml.sax.saxutils import escape

from belvedere.description.urdf import Box, Cylinder, Inertial, Pose, Sphere
from belvedere.errors import BelvedereError, ParseError, SourceLocation
from belvedere.world._model import RGBA, Material, Shape, WorldLink, WorldModelEntry
from belvedere.world._paths import BUILTIN_MODELS, ModelPaths, model_sdf_file
from belvedere.world._sdf import read_world_string
from belvedere.xmldom import parse_file

__all__ = [
    "SHAPES",
    "LibraryError",
    "LibraryModel",
    "load_model",
    "model_library",
    "simple_shape",
]

logger = logging.getLogger(__name__)

_BUILTIN_NAMES = {"ground_plane": "Ground Plane", "sun": "Sun"}
"""The names Gazebo's own model.config files give its built-ins."""


class LibraryError(ParseError):
    """A model of the library that cannot be inserted."""


@dataclass(frozen=True, slots=True)
class LibraryModel:
    """One model of the library."""

    name: str
    """Its ``<name>`` in ``model.config`` (the directory's name when it has none)."""
    uri: str
    """``model://DIRECTORY``: what a world's ``<include>`` writes."""
    directory: Path | None
    """None: built into belvedere."""
    description: str = ""
    error: str | None = None
    """Why it cannot be inserted (``file:line: error: …``); None when it can."""
    problem: BelvedereError | None = field(default=None, compare=False, repr=False)
    light: bool = False
    """A light (the built-in sun), which Gazebo lists with the models."""
    """The error itself (raised again by :func:`load_model`)."""

    @property
    def ok(self) -> bool:
        return self.error is None


def model_library(paths: ModelPaths) -> list[LibraryModel]:
    """Every model on ``paths``, in search order (each directory's models by name), then
    the built-ins no directory provides."""
    found: list[LibraryModel] = []
    seen: set[str] = set()
    for base in paths.directories:
        try:
            children = sorted(os.scandir(base), key=lambda e: e.name)
        except OSError:
            continue  # a path entry that does not exist lists nothing, as in Gazebo
        for child in children:
            if child.name.startswith(".") or child.name in seen or not child.is_dir():
                continue
            model = _read_entry(Path(child.path), paths)
            if model is not None:
                seen.add(child.name)
                found.append(model)
    for name in BUILTIN_MODELS:
        if name not in seen:
            builtin = LibraryModel(_BUILTIN_NAMES[name], f"model://{name}", None, "built in")
            found.append(replace(builtin, light=name == "sun"))
    return found


def _read_entry(directory: Path, paths: ModelPaths) -> LibraryModel | None:
    uri = f"model://{directory.name}"
    config = directory / "model.config"
    if not config.is_file():
        if not any(p.suffix == ".sdf" for p in directory.iterdir()):
            return None  # not a model directory (a ``materials`` folder, say)
        where = SourceLocation(str(config))
        msg = "no model.config (Gazebo lists a model by its model.config)"
        err = LibraryError(msg, where)
        return LibraryModel(directory.name, uri, directory, error=_first_line(err), problem=err)
    name, description = directory.name, ""
    try:
        doc = parse_file(config, namespaces=False, keep_blank=False)
        for el in doc.root.elements():
            if el.tag == "name" and el.text_content().strip():
                name = el.text_content().strip()
            elif el.tag == "description":
                description = " ".join(el.text_content().split())
        if doc.root.tag != "model":
            msg = f"expected a <model> document, found <{doc.root.tag}>"
            raise LibraryError(msg, doc.root.loc)
        _read(uri, paths, directory)
    except BelvedereError as err:
        return LibraryModel(name, uri, directory, description, _first_line(err), err)
    return LibraryModel(name, uri, directory, description)


def _first_line(err: BelvedereError) -> str:
    return err.describe().splitlines()[0]


def load_model(model: LibraryModel, paths: ModelPaths) -> WorldModelEntry:
    """The model as a world would include it (``uri`` set), posed as its file poses it.

    Raises:
        SDFError: its SDF cannot be read (the error the listing showed).
        LibraryError: it has no usable ``model.config``, or is not a model (the sun is a
            light).
    """
    if model.problem is not None:
        raise model.problem
    return _read(model.uri, paths, model.directory)


def _read(uri: str, paths: ModelPaths, directory: Path | None) -> WorldModelEntry:
    """The model read as an ``<include>`` of ``uri`` reads it."""
    where = SourceLocation(uri)
    if directory is not None:
        sdf_file = model_sdf_file(directory)
        where = SourceLocation(str(sdf_file))
        if not sdf_file.is_file():
            msg = f"{uri}: its model.config names {sdf_file.name}, which does not exist"
            raise LibraryError(msg, SourceLocation(str(directory / "model.config")))
    text = (
        "<sdf version='1.6'><world name='library'>"
        f"<include><uri>{escape(uri)}</uri></include></world></sdf>"
    )
    world = read_world_string(text, f"<{uri}>", model_paths=paths)
    if not world.models:
        msg = f"{uri} is a light, not a model: only models can be inserted"
        raise LibraryError(msg, where)
    return replace(world.models[0], source=where)


SHAPES = ("box", "cylinder", "sphere")
"""The simple shapes Gazebo's toolbar inserts (``unit_box`` …)."""


def simple_shape(kind: str, *, rgba: RGBA = (0.7, 0.7, 0.7, 1.0)) -> WorldModelEntry:
    """Gazebo's ``unit_box``, ``unit_cylinder`` or ``unit_sphere``: a metre across, 1 kg,
    dynamic, its frame at its centre (insert it half a metre up). It has no ``uri``: a
    saved world writes it inline."""
    geometry: Box | Cylinder | Sphere
    if kind == "box":
        geometry, moments = Box((1.0, 1.0, 1.0)), (1 / 6, 1 / 6, 1 / 6)
    elif kind == "cylinder":
        # 1/12 m (3 r^2 + l^2) across, m r^2 / 2 about the axis
        geometry, moments = Cylinder(0.5, 1.0), (7 / 48, 7 / 48, 1 / 8)
    elif kind == "sphere":
        geometry, moments = Sphere(0.5), (0.1, 0.1, 0.1)
    else:
        msg = f"no simple shape {kind!r} (shapes: {', '.join(SHAPES)})"
        raise LibraryError(msg)
    ixx, iyy, izz = moments
    inertial = Inertial(mass=1.0, ixx=ixx, ixy=0.0, ixz=0.0, iyy=iyy, iyz=0.0, izz=izz)
    material = Material(ambient=rgba, diffuse=rgba)
    link = WorldLink(
        "link",
        inertial=inertial,
        collisions=(Shape("collision", geometry),),
        visuals=(Shape("visual", geometry, rgba=rgba, material=material),),
    )
    return WorldModelEntry(
        name=f"unit_{kind}", pose=Pose((0.0, 0.0, 0.5)), links=(link,), canonical_link="link"
    )
