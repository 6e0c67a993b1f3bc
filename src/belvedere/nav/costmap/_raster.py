"""Cells along lines and inside polygons, vectorised, as costmap_2d's Bresenham walks them."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = ["convex_fill", "raytrace"]

Cells = npt.NDArray[np.int64]


def raytrace(x0: int, y0: int, ends: Cells, max_length: float) -> tuple[Cells, Cells]:
    """The cells (columns, rows) of costmap_2d's ``raytraceLine`` from (x0, y0) to each end
    (M, 2) at once: Bresenham along the dominant axis, cut at ``max_length`` cells of the
    ray's length, the cell where it stops included."""
    starts = np.broadcast_to(np.array([x0, y0], dtype=np.int64), np.shape(ends))
    return _lines(starts, ends, max_length)


def _lines(starts: Cells, ends: Cells, max_length: float) -> tuple[Cells, Cells]:
    """:func:`raytrace` with a start cell per line."""
    if len(ends) == 0:
        empty = np.empty(0, dtype=np.int64)
        return empty, empty
    dx = ends[:, 0] - starts[:, 0]
    dy = ends[:, 1] - starts[:, 1]
    adx, ady = np.abs(dx), np.abs(dy)
    dist = np.hypot(dx, dy)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(dist == 0, 1.0, np.minimum(1.0, max_length / dist))
    x_major = adx >= ady
    da = np.where(x_major, adx, ady)
    db = np.where(x_major, ady, adx)
    steps = (scale * da).astype(np.int64)
    counts = steps + 1
    ray = np.repeat(np.arange(len(ends)), counts)
    first = np.cumsum(counts) - counts
    i = np.arange(int(counts.sum())) - first[ray]
    da_r = da[ray]
    minor = np.where(da_r > 0, (da_r // 2 + i * db[ray]) // np.maximum(da_r, 1), 0)
    sx, sy = np.sign(dx)[ray], np.sign(dy)[ray]
    xm = x_major[ray]
    cols = starts[ray, 0] + np.where(xm, i * sx, minor * sx)
    rows = starts[ray, 1] + np.where(xm, minor * sy, i * sy)
    return cols, rows


def convex_fill(vertices: Cells, width: int, height: int) -> tuple[Cells, Cells]:
    """costmap_2d's ``convexFillCells``: the polygon's outline (lines between its vertex
    cells) and, in each column, every cell between the outline's lowest and highest; clipped to
    the grid."""
    vertices = np.asarray(vertices, dtype=np.int64).reshape(-1, 2)
    cols, rows = _lines(vertices, np.roll(vertices, -1, axis=0), np.inf)
    low_col = int(cols.min())
    span = int(cols.max()) - low_col + 1
    low = np.full(span, np.iinfo(np.int64).max, dtype=np.int64)
    high = np.full(span, np.iinfo(np.int64).min, dtype=np.int64)
    np.minimum.at(low, cols - low_col, rows)
    np.maximum.at(high, cols - low_col, rows)
    lengths = high - low + 1
    column = np.repeat(np.arange(span), lengths)
    offsets = np.arange(int(lengths.sum())) - np.repeat(np.cumsum(lengths) - lengths, lengths)
    fill_cols = column + low_col
    fill_rows = low[column] + offsets
    inside = (fill_cols >= 0) & (fill_cols < width) & (fill_rows >= 0) & (fill_rows < height)
    return fill_cols[inside], fill_rows[inside]
