"""Pictures of maps: the grid in map_saver's greys, with a trajectory drawn over it."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from belvedere.maps._model import OccupancyMap

if TYPE_CHECKING:
    from PIL import Image

__all__ = ["map_picture", "map_summary"]

MIN_SIDE = 400
"""Small maps are enlarged (by whole pixels per cell) to at least this many pixels a side,
so a trajectory over them can be seen."""


def _greys(data: npt.NDArray[np.int8]) -> npt.NDArray[np.uint8]:
    """Free 254, occupied 0, unknown 205 (map_saver's); scale values shade between."""
    cells = data.astype(np.int16)
    known = (cells >= 0) & (cells <= 100)
    pixels = np.full(cells.shape, 205, dtype=np.uint8)
    pixels[known] = (254 - (cells[known] * 254 + 50) // 100).astype(np.uint8)
    return pixels


def map_picture(
    grid: OccupancyMap, *, trajectory: npt.NDArray[np.float64] | None = None
) -> Image.Image:
    """An RGB picture of ``grid`` (its top row is the grid's last), with ``trajectory`` (TUM
    rows in the map frame) as a line from a green start dot to a red end dot."""
    from PIL import Image, ImageDraw

    scale = max(1, math.ceil(MIN_SIDE / max(grid.width, grid.height)))
    grey = _greys(grid.data[::-1])
    picture = Image.fromarray(grey).convert("RGB")
    if scale > 1:
        picture = picture.resize(
            (grid.width * scale, grid.height * scale), Image.Resampling.NEAREST
        )
    if trajectory is not None and len(trajectory):
        height = grid.height * scale
        points = []
        for x, y in trajectory[:, 1:3]:
            col, row = grid.world_to_cell(float(x), float(y))
            points.append((col * scale, height - row * scale))
        draw = ImageDraw.Draw(picture)
        width = max(1, scale // 2, round(max(picture.size) / 400))
        if len(points) > 1:
            draw.line(points, fill=(30, 90, 230), width=width, joint="curve")
        r = 2 * width + 1
        for (px, py), colour in ((points[0], (20, 170, 40)), (points[-1], (220, 30, 30))):
            draw.ellipse((px - r, py - r, px + r, py + r), fill=colour)
    return picture


def map_summary(grid: OccupancyMap) -> str:
    """One line: size, resolution, extent and how much is free, occupied and unknown."""
    cells = grid.data
    total = max(1, cells.size)
    free = int(np.count_nonzero(cells == 0))
    occupied = int(np.count_nonzero(cells == 100))
    unknown = int(np.count_nonzero(cells < 0))
    w_m, h_m = grid.width * grid.resolution, grid.height * grid.resolution
    return (
        f"{grid.width} x {grid.height} cells @ {grid.resolution:.3f} m "
        f"({w_m:.2f} x {h_m:.2f} m, origin {grid.origin[0]:g}, {grid.origin[1]:g}): "
        f"{100 * free / total:.0f}% free, {100 * occupied / total:.0f}% occupied, "
        f"{100 * unknown / total:.0f}% unknown"
    )
