"""Reading maps as map_server 1.x reads them: the YAML description, its image, and the
occupancy values it computes from the pixels."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
import numpy.typing as npt
import yaml

from belvedere.bounded import YAML_TEXT_BYTES, LimitError, read_regular_text
from belvedere.errors import ParseError, SourceLocation
from belvedere.maps._image import ImageError, MapImage, read_map_image
from belvedere.maps._model import MapError, OccupancyMap
from belvedere.yamlfile import YamlDocument, load_yaml

__all__ = [
    "DEFAULT_FREE_THRESH",
    "DEFAULT_OCCUPIED_THRESH",
    "MODES",
    "MapMode",
    "MapYaml",
    "load_image_map",
    "load_map",
    "occupancy_from_pixels",
    "read_map_yaml",
]

MapMode = Literal["trinary", "scale", "raw"]
MODES: tuple[MapMode, ...] = ("trinary", "scale", "raw")
DEFAULT_OCCUPIED_THRESH = 0.65
DEFAULT_FREE_THRESH = 0.196
"""map_server's defaults for the old ``map_server IMAGE RESOLUTION`` form."""

_REQUIRED = "image, resolution, origin, negate, occupied_thresh and free_thresh"


@dataclass(frozen=True)
class MapYaml:
    """A map's YAML description, checked."""

    image: Path
    """The image file (a relative ``image:`` is taken relative to the YAML's directory)."""
    resolution: float
    origin: tuple[float, float, float]
    negate: bool
    occupied_thresh: float
    free_thresh: float
    mode: MapMode = "trinary"
    image_at: SourceLocation | None = None
    """Where ``image:`` is written (for errors about the image)."""

    def load(self) -> OccupancyMap:
        """The map: the image read with these settings.

        Raises:
            MapError: the image cannot be read (at ``image:``'s line, naming the image).
        """
        return load_image_map(
            self.image,
            self.resolution,
            origin=self.origin,
            negate=self.negate,
            occupied_thresh=self.occupied_thresh,
            free_thresh=self.free_thresh,
            mode=self.mode,
            image_at=self.image_at,
        )


def _number(doc: YamlDocument, *keys: str | int) -> float | None:
    """A number as yaml-cpp's ``as<double>`` reads one (``5e-2`` too, which YAML 1.1 leaves
    a string); None if the value is not one."""
    value: Any = doc.data
    for key in keys:
        value = value[key]
    if isinstance(value, bool):
        return None
    if isinstance(value, int | float):
        try:
            return float(value)
        except OverflowError:  # an int of hundreds of digits: yaml-cpp fails to convert it too
            return None
    if isinstance(value, str):
        try:
            return float(value.strip())
        except ValueError:
            return None
    return None


def _shown(doc: YamlDocument, *keys: str | int) -> str:
    """A value for a message: strings quoted, the rest as YAML writes them (a long one cut
    to its start)."""
    value: Any = doc.data
    for key in keys:
        value = value[key]
    if isinstance(value, str):
        text = repr(value)
    elif isinstance(value, bool):
        text = str(value).lower()
    else:
        text = "nothing" if value is None else str(value)
    return text if len(text) <= 80 else text[:76] + "…"


def _scalar_text(doc: YamlDocument, key: str) -> str | None:
    """The value of ``key`` as written (``image: 007.pgm`` is not the number 7)."""
    root = doc.root
    if not isinstance(root, yaml.MappingNode):
        return None
    for key_node, value_node in root.value:
        if isinstance(key_node, yaml.ScalarNode) and key_node.value == key:
            return str(value_node.value) if isinstance(value_node, yaml.ScalarNode) else None
    return None


def read_map_yaml(path: str | os.PathLike[str], *, text: str | None = None) -> MapYaml:
    """Read and check a map's YAML description (``text``: its content, already read).

    Raises:
        MapError: the file cannot be read, is not YAML, or lacks or misstates a key (at its
            line).
    """
    shown = os.fspath(path)
    if text is None:
        try:
            text = read_regular_text(
                path, limit=YAML_TEXT_BYTES, what="the map file", name=repr(shown)
            )
        except LimitError as err:
            raise MapError(err.message, err.location) from None
    try:
        doc = load_yaml(text, path=shown)
    except ParseError as err:
        raise MapError(err.message, err.location, hint=err.hint) from None
    data = doc.data
    top = SourceLocation(shown, 1, 1)
    if not isinstance(data, dict):
        msg = f"a map's YAML is a mapping of {_REQUIRED}; this file holds " + (
            "nothing" if data is None else f"a {type(data).__name__}"
        )
        raise MapError(msg, doc.location() if data is not None else top)

    def require(key: str) -> None:
        if key not in data:
            msg = f"the map has no {key!r} (map_server needs {_REQUIRED})"
            raise MapError(msg, top)

    def number(key: str, what: str, *, positive: bool = False) -> float:
        require(key)
        value = _number(doc, key)
        if value is None or not math.isfinite(value) or (positive and value <= 0):
            msg = f"{key} must be {what}, got {_shown(doc, key)}"
            raise MapError(msg, doc.location(key))
        return value

    resolution = number("resolution", "a positive number of metres per cell", positive=True)
    require("negate")
    negate = data["negate"]
    if isinstance(negate, bool):
        negate = int(negate)
    if not isinstance(negate, int):
        msg = f"negate must be 0 or 1, got {_shown(doc, 'negate')}"
        raise MapError(msg, doc.location("negate"))
    occupied = number("occupied_thresh", "a number (a probability, 0.65 say)")
    free = number("free_thresh", "a number (a probability, 0.196 say)")
    mode: MapMode = "trinary"
    if "mode" in data:
        text_mode = _scalar_text(doc, "mode")
        if text_mode not in MODES:
            msg = f"mode must be trinary, scale or raw, got {_shown(doc, 'mode')}"
            raise MapError(msg, doc.location("mode"))
        mode = text_mode
    require("origin")
    origin = data["origin"]
    if not isinstance(origin, list) or len(origin) < 3:
        msg = f"origin must be [x, y, yaw], got {_shown(doc, 'origin')}"
        raise MapError(msg, doc.location("origin"))
    xyz: list[float] = []
    for i in range(3):
        value = _number(doc, "origin", i)
        if value is None or not math.isfinite(value):
            msg = f"origin must be [x, y, yaw] in metres and radians, got {_shown(doc, 'origin')}"
            raise MapError(msg, doc.location("origin", i))
        xyz.append(value)
    require("image")
    image = _scalar_text(doc, "image")
    if image is None or data["image"] is None or not image.strip():
        msg = "image must name the map's image file (map.pgm, say), relative to this file"
        raise MapError(msg, doc.location("image"))
    image_path = Path(image)
    if not image_path.is_absolute():
        image_path = Path(os.path.dirname(shown)) / image_path
    return MapYaml(
        image=image_path,
        resolution=resolution,
        origin=(xyz[0], xyz[1], xyz[2]),
        negate=bool(negate),
        occupied_thresh=occupied,
        free_thresh=free,
        mode=mode,
        image_at=doc.location("image"),
    )


def occupancy_from_pixels(
    image: MapImage,
    *,
    negate: bool,
    occupied_thresh: float,
    free_thresh: float,
    mode: MapMode = "trinary",
) -> npt.NDArray[np.int8]:
    """The grid map_server makes of an image: ``(height, width)`` int8, the image's bottom
    row first (grid row 0).

    Per pixel, as map_server's loader: the mean of its bytes (without alpha, unless the mode
    is trinary), inverted if ``negate``; ``raw`` keeps that mean (truncated to a byte, so
    values above 127 wrap to negative int8); otherwise ``p = (255 - mean) / 255`` is
    occupied (100) above ``occupied_thresh``, free (0) below ``free_thresh``, and between
    them unknown (-1) in trinary mode or where alpha is 0, else ``1 + 98 * (p - free) /
    (occupied - free)``, truncated."""
    pixels = image.pixels
    height, width = pixels.shape[:2]
    cells = np.empty((height, width), dtype=np.int8)
    # a block of rows at a time: the arithmetic's float64 temporaries stay a few MiB however
    # large the map (a map up to the block's size, most of them, is one block)
    rows = max(1, _BLOCK_CELLS // max(1, width))
    for top in range(0, height, rows):
        block = pixels[top : top + rows]
        # the image's top row is the grid's last
        cells[height - top - len(block) : height - top] = _occupancy(
            block, image.has_alpha, negate, occupied_thresh, free_thresh, mode
        )[::-1]
    return cells


_BLOCK_CELLS = 1 << 20
"""Pixels turned into cells at a time."""


def _occupancy(
    pixels: npt.NDArray[np.uint8],
    has_alpha: bool,
    negate: bool,
    occupied_thresh: float,
    free_thresh: float,
    mode: MapMode,
) -> npt.NDArray[np.int8]:
    """:func:`occupancy_from_pixels` for a block of rows, top row first."""
    channels = pixels.shape[2]
    averaged = channels if mode == "trinary" or not has_alpha else channels - 1
    total = pixels[..., :averaged].sum(axis=-1, dtype=np.int64)
    mean = total / float(averaged)
    if negate:
        mean = 255 - mean
    if mode == "raw":
        raw: npt.NDArray[np.int8] = np.trunc(mean).astype(np.uint8).view(np.int8)
        return raw
    occ = (255 - mean) / 255.0
    cells = np.full(mean.shape, -1, dtype=np.int8)
    between = ~(occ > occupied_thresh) & ~(occ < free_thresh)
    if mode == "scale":
        # SDL's alpha is the last byte of the pixel, whatever it holds (blue in RGB); a
        # one-byte pixel counts as opaque.
        alpha = pixels[..., channels - 1] if channels > 1 else np.ones(mean.shape, np.uint8)
        shaded = between & (alpha >= 1)
        # thresholds a hair apart make a huge ratio: clipped to 255 below, as in the loop
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            ratio = (occ - free_thresh) / (occupied_thresh - free_thresh)
            value = np.trunc(1 + 98 * ratio)
        cells[shaded] = np.clip(value[shaded], 0, 255).astype(np.uint8).view(np.int8)
    cells[occ > occupied_thresh] = 100
    cells[(occ < free_thresh) & ~(occ > occupied_thresh)] = 0
    return cells


def load_image_map(
    image: str | os.PathLike[str],
    resolution: float,
    *,
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0),
    negate: bool = False,
    occupied_thresh: float = DEFAULT_OCCUPIED_THRESH,
    free_thresh: float = DEFAULT_FREE_THRESH,
    mode: MapMode = "trinary",
    image_at: SourceLocation | None = None,
) -> OccupancyMap:
    """The map an image makes with these settings (the old ``map_server IMAGE RES`` form uses
    the defaults).

    Raises:
        MapError: the image cannot be read (at ``image_at``, naming the image and why).
    """
    shown = os.fspath(image)
    try:
        pixels = read_map_image(image)
    except LimitError as err:
        raise MapError(err.message, image_at) from None
    except OSError as err:
        reason = err.strerror or str(err)
        msg = f"cannot read the map image {shown!r}: {reason}"
        raise MapError(msg, image_at) from None
    except ImageError as err:
        msg = f"cannot read the map image {shown!r}: {err}"
        raise MapError(msg, image_at) from None
    cells = occupancy_from_pixels(
        pixels,
        negate=negate,
        occupied_thresh=occupied_thresh,
        free_thresh=free_thresh,
        mode=mode,
    )
    return OccupancyMap(cells, resolution, origin)


def load_map(path: str | os.PathLike[str]) -> OccupancyMap:
    """The map a map_server YAML file describes.

    Raises:
        MapError: the YAML or its image is wrong (at the YAML's line, naming the image).
    """
    return read_map_yaml(path).load()
