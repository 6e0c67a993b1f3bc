"""Writing maps exactly as map_saver 1.x writes them: ``NAME.pgm`` and ``NAME.yaml``."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from belvedere.fileio import stage_write
from belvedere.maps._model import OccupancyMap, yaw_from_quat_xyzw

__all__ = [
    "DEFAULT_SAVE_FREE",
    "DEFAULT_SAVE_OCCUPIED",
    "map_pgm_bytes",
    "map_yaml_text",
    "save_map",
]

DEFAULT_SAVE_OCCUPIED = 65
DEFAULT_SAVE_FREE = 25
"""map_saver's ``--occ`` and ``--free`` defaults (percent)."""

PIXEL_FREE = 254
PIXEL_OCCUPIED = 0
PIXEL_UNKNOWN = 205


def _float32(value: float) -> float:
    """The message carries the resolution as a float32; map_saver prints that."""
    return float(np.float32(value))


def map_pgm_bytes(
    grid: OccupancyMap,
    *,
    occupied: int = DEFAULT_SAVE_OCCUPIED,
    free: int = DEFAULT_SAVE_FREE,
) -> bytes:
    """The P5 PGM map_saver writes: cells from 0 to ``free`` are 254, from ``occupied`` up
    0, the rest (unknown, and what lies between) 205; the grid's last row is the image's
    top row."""
    header = (
        f"P5\n# CREATOR: map_saver.cpp {_float32(grid.resolution):.3f} m/pix\n"
        f"{grid.width} {grid.height}\n255\n"
    )
    cells = grid.data[::-1]
    pixels = np.full(cells.shape, PIXEL_UNKNOWN, dtype=np.uint8)
    pixels[cells >= occupied] = PIXEL_OCCUPIED
    pixels[(cells >= 0) & (cells <= free)] = PIXEL_FREE
    return header.encode("ascii") + pixels.tobytes()


def map_yaml_text(grid: OccupancyMap, image: str) -> str:
    """The YAML map_saver writes beside the image (``image``: the name as it names it, the
    ``-f`` name plus ``.pgm``). Its thresholds are map_server's defaults whatever ``--occ``
    and ``--free`` were, as map_saver's are."""
    x, y, _ = grid.origin
    yaw = yaw_from_quat_xyzw(grid.quat_xyzw)
    return (
        f"image: {image}\n"
        f"resolution: {_float32(grid.resolution):f}\n"
        f"origin: [{x:f}, {y:f}, {yaw:f}]\n"
        "negate: 0\n"
        "occupied_thresh: 0.65\n"
        "free_thresh: 0.196\n"
        "\n"
    )


def save_map(
    name: str | os.PathLike[str],
    grid: OccupancyMap,
    *,
    occupied: int = DEFAULT_SAVE_OCCUPIED,
    free: int = DEFAULT_SAVE_FREE,
) -> tuple[Path, Path]:
    """Write ``NAME.pgm`` and ``NAME.yaml`` as ``map_saver -f NAME`` does, each whole or not
    at all (both are written out before either replaces a file). Returns their paths.

    Raises:
        FileWriteError: a file could not be written (the one already in place stays whole).
    """
    base = os.fspath(name)
    pgm, yaml_file = base + ".pgm", base + ".yaml"
    staged_pgm = stage_write(pgm, map_pgm_bytes(grid, occupied=occupied, free=free))
    try:
        staged_yaml = stage_write(yaml_file, map_yaml_text(grid, pgm))
    except BaseException:
        staged_pgm.discard()
        raise
    try:
        written_pgm = staged_pgm.commit()
    except BaseException:
        staged_yaml.discard()
        raise
    return written_pgm, staged_yaml.commit()
