"""A growable likelihood grid: where scan end points fell, and the smooth field matched against.

Each cell counts the end points that fell in it; a cell's weight is its count over
``saturation`` (capped at 1), so a stray reading weighs less than a wall seen again and again.
The field is the upper envelope of a Gaussian of the distance to each cell's points (their
mean, so that the field follows the points within a cell, as GMapping's mean hit positions
do), times the cell's weight, cut ``radius`` cells away — a likelihood field — kept up to date
as points arrive (weights only grow, so stamping ``max(field, stamp)`` is exact but for the
mean's later moves within its cell). Matching samples it bilinearly between cell centres.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator

import numpy as np
import numpy.typing as npt

from belvedere.bounded import GRID_CELLS, LimitError

__all__ = ["FieldGrid", "FreeGrid", "GridLimitError"]

Array = npt.NDArray[np.float64]
Grid = npt.NDArray[np.float32]

_GROW_MARGIN = 10.0
"""Metres added around the needed area whenever a grid grows (so that it grows seldom)."""

_BATCH_SAMPLES = 1 << 21
"""Samples along beams placed at once when counting crossings (a memory bound: 65,536 beams
of 144 m would otherwise take 2 GiB)."""


class GridLimitError(LimitError):
    """A grid that would grow past :data:`GRID_CELLS`: to ``cells``."""

    def __init__(self, cells: float) -> None:
        self.cells = cells
        size = f"{cells:,.0f}" if math.isfinite(cells) else str(cells)
        super().__init__(f"a grid of {size} cells, more than the cap of {GRID_CELLS:,}")


def _layout(
    origin: Array | None, res: float, lo: Array, hi: Array, margin: float
) -> tuple[Array, int, int]:
    """A grid's origin, rows and columns holding ``[lo, hi]`` plus ``margin`` (keeping the
    cell boundaries of ``origin`` when there is one); less margin, down to none, when the
    margin would take the grid past :data:`GRID_CELLS`.

    Raises:
        GridLimitError: even without a margin, more than :data:`GRID_CELLS` cells.
    """
    for m in (margin, 0.0):
        if origin is not None:
            new_lo = origin + np.floor((lo - m - origin) / res) * res
        else:
            new_lo = np.floor((lo - m) / res) * res
        cols = np.ceil((hi[0] + m - new_lo[0]) / res)
        rows = np.ceil((hi[1] + m - new_lo[1]) / res)
        cells = float(rows * cols)
        if cells <= GRID_CELLS:  # (False for NaN)
            return new_lo, int(rows), int(cols)
    raise GridLimitError(cells)


def _batches(steps: npt.NDArray[np.int64], budget: int) -> Iterator[slice]:
    """Consecutive runs of items whose ``steps`` sum to about ``budget`` (at least one each)."""
    cum = np.cumsum(steps)
    begin = 0
    done = 0
    while begin < len(steps):
        end = max(begin + 1, int(np.searchsorted(cum, done + budget, side="right")))
        yield slice(begin, end)
        done = int(cum[end - 1])
        begin = end


class FieldGrid:
    """Cells of ``resolution`` metres; cell (row j, column i) covers
    ``origin + [i, i+1)·res x [j, j+1)·res`` of the grid's own frame."""

    def __init__(
        self, resolution: float, sigma: float, radius: int, saturation: float = 2.0
    ) -> None:
        self.resolution = resolution
        self.sigma = sigma
        self.radius = radius
        self.saturation = saturation
        self.origin = np.zeros(2)
        self.hits: Grid = np.zeros((0, 0), dtype=np.float32)
        self.field: npt.NDArray[np.float64] = np.zeros((0, 0))
        """Float64 while the grid grows: arithmetic on it then needs no conversions."""
        self.points = 0
        self.version = 0
        """How many inserts the grid has had: whoever reads it can tell whether it changed."""
        self._undo: tuple[npt.NDArray[np.intp], Array] | None = None
        """The cells the last insert raised and their values before it (if it kept them)."""

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.hits.shape[0]), int(self.hits.shape[1]))

    def bounds(self) -> tuple[Array, Array]:
        """The (x, y) corners of the area the grid covers."""
        size = np.array([self.shape[1], self.shape[0]], dtype=np.float64) * self.resolution
        return self.origin.copy(), self.origin + size

    def _ensure(self, lo: Array, hi: Array) -> None:
        layout = self.layout(lo, hi)
        if layout is None:
            return
        new_lo, rows, cols = layout
        hits = np.zeros((rows, cols), dtype=np.float32)
        field = np.zeros((rows, cols))
        if self.hits.size:
            di, dj = np.rint((self.origin - new_lo) / self.resolution).astype(int)
            h, w = self.shape
            hits[dj : dj + h, di : di + w] = self.hits
            field[dj : dj + h, di : di + w] = self.field
        self.origin = new_lo
        self.hits = hits
        self.field = field

    def layout(self, lo: Array, hi: Array) -> tuple[Array, int, int] | None:
        """The origin, rows and columns the grid takes to hold points in ``[lo, hi]`` (None:
        it holds them already), never more than :data:`GRID_CELLS` cells.

        Raises:
            GridLimitError: holding them takes more cells than that.
        """
        pad = (self.radius + 2) * self.resolution
        lo = lo - pad
        hi = hi + pad
        have_lo, have_hi = self.bounds()
        if self.hits.size and np.all(lo >= have_lo) and np.all(hi <= have_hi):
            return None
        if self.hits.size:
            lo = np.minimum(lo, have_lo)
            hi = np.maximum(hi, have_hi)
        # Grow by whole cells so that old cells keep their boundaries, and by a margin that
        # grows with the grid (so that a grid growing step by step is copied seldom).
        margin = _GROW_MARGIN
        if self.hits.size:
            margin = max(margin, 0.25 * float(np.max(have_hi - have_lo)))
        origin = self.origin if self.hits.size else None
        return _layout(origin, self.resolution, lo, hi, margin)

    def insert(self, points: Array, *, undoable: bool = False) -> None:
        """Add end points ``(N, 2)`` given in the grid's frame; ``undoable`` keeps what they
        overwrite, for :meth:`before_last_insert`."""
        if not len(points):
            return
        self.version += 1
        self._undo = (np.zeros(0, dtype=np.intp), np.zeros(0)) if undoable else None
        self._ensure(points.min(axis=0), points.max(axis=0))
        res = self.resolution
        ij = np.floor((points - self.origin) / res).astype(np.int64)
        width = self.shape[1]
        flat = ij[:, 1] * width + ij[:, 0]
        cells, where, counts = np.unique(flat, return_inverse=True, return_counts=True)
        hits = self.hits.reshape(-1)
        old = hits[cells]
        new = old + counts.astype(np.float32)
        hits[cells] = new
        self.points += len(points)
        w_old = np.minimum(old / self.saturation, 1.0)
        w_new = np.minimum(new / self.saturation, 1.0)
        grown = w_new > w_old
        if not grown.any():
            return
        # The kernel is centred on the mean of the cell's new points, not on the cell's
        # centre: a wall on a cell boundary would otherwise move half a cell.
        mean_x = np.bincount(where, weights=points[:, 0])[grown] / counts[grown]
        mean_y = np.bincount(where, weights=points[:, 1])[grown] / counts[grown]
        grown_cells = cells[grown]
        r = self.radius
        dj, di = np.mgrid[-r : r + 1, -r : r + 1]
        offsets = (dj * width + di).reshape(-1)
        ci = grown_cells % width
        cj = grown_cells // width
        cx = self.origin[0] + (ci[:, None] + di.reshape(1, -1) + 0.5) * res
        cy = self.origin[1] + (cj[:, None] + dj.reshape(1, -1) + 0.5) * res
        d2 = (cx - mean_x[:, None]) ** 2 + (cy - mean_y[:, None]) ** 2
        values = w_new[grown][:, None] * np.exp(d2 * (-0.5 / (self.sigma * self.sigma)))
        idx = (grown_cells[:, None] + offsets[None, :]).reshape(-1)
        if undoable:
            self._undo = (idx, self.field.reshape(-1)[idx])
        np.maximum.at(self.field.reshape(-1), idx, values.reshape(-1))

    @property
    def undoable(self) -> bool:
        """Whether the last insert kept what it overwrote."""
        return self._undo is not None

    @contextlib.contextmanager
    def before_last_insert(self) -> Iterator[None]:
        """The field as it was before the last insert (which must have been ``undoable``)
        while the ``with`` lasts; as it is after it again, to the bit, when it ends."""
        if self._undo is None:
            message = "the last insert kept nothing to undo"
            raise RuntimeError(message)
        idx, before = self._undo
        flat = self.field.reshape(-1)
        after = flat[idx]
        # (a cell stamped twice is listed twice, with the same value both times)
        flat[idx] = before
        try:
            yield
        finally:
            flat[idx] = after

    def finish(self) -> None:
        """Drop what only growing needs: the counts, and the empty border beyond the
        kernel's reach; the field becomes float32 (half the memory)."""
        field = self.field
        rows = np.flatnonzero(field.any(axis=1))
        cols = np.flatnonzero(field.any(axis=0))
        if len(rows):
            pad = 2
            r0 = max(rows[0] - pad, 0)
            c0 = max(cols[0] - pad, 0)
            width = field.shape[1]
            field = field[r0 : rows[-1] + pad + 1, c0 : cols[-1] + pad + 1]
            self.origin = self.origin + np.array([c0, r0]) * self.resolution
            if self._undo is not None:
                # The kept cells, renumbered; those cut off held 0 and hold 0 before too.
                j, i = np.divmod(self._undo[0], width)
                j, i = j - r0, i - c0
                h, w = field.shape
                inside = (j >= 0) & (j < h) & (i >= 0) & (i < w)
                self._undo = ((j * w + i)[inside], self._undo[1][inside])
        self.field = np.ascontiguousarray(field, dtype=np.float32)
        self.hits = np.zeros((0, 0), dtype=np.float32)

    def sample(self, points: Array) -> tuple[Array, Array]:
        """The field at points ``(N, 2)`` of the grid's frame, bilinearly interpolated between
        cell centres, and its gradient (per metre); zero off the grid."""
        return self.sample_xy(points[:, 0], points[:, 1])

    def sample_xy(self, x: Array, y: Array) -> tuple[Array, Array]:
        """:meth:`sample` with the coordinates apart; returns the value and ``(gx, gy)``
        stacked as a (2, N) array."""
        inv = 1.0 / self.resolution
        ux = x * inv - (self.origin[0] * inv + 0.5)
        uy = y * inv - (self.origin[1] * inv + 0.5)
        h, w = self.field.shape
        # Cells within radius + 2 of the border never hold any weight (insert pads), so a point
        # off the grid clamped onto the border reads 0 with a zero gradient, as it should.
        ix = np.clip(np.floor(ux), 0, w - 2)
        iy = np.clip(np.floor(uy), 0, h - 2)
        fx = np.clip(ux - ix, 0.0, 1.0)
        fy = np.clip(uy - iy, 0.0, 1.0)
        flat = (iy * w + ix).astype(np.intp)
        value, gx, gy = bilinear(self.field.reshape(-1), w, flat, fx, fy)
        grad = np.empty((2, len(x)))
        grad[0] = gx * inv
        grad[1] = gy * inv
        return value, grad


def bilinear(
    field: Array, width: int, flat: npt.NDArray[np.intp], fx: Array, fy: Array
) -> tuple[Array, Array, Array]:
    """A field flattened row by row (``width`` columns) interpolated between four cell
    centres, the lower-left one at ``flat``, at fractions ``fx``, ``fy`` towards the others:
    the value and its slopes along x and y, per cell. The corners are taken as they are (no
    clamping): the scan matcher clamps only when a point leaves the grid, in its inner loop."""
    v00 = field[flat]
    v10 = field[flat + 1]
    v01 = field[flat + width]
    v11 = field[flat + (width + 1)]
    d0 = v10 - v00
    d1 = v11 - v01
    a = v00 + d0 * fx
    ba = v01 + d1 * fx - a
    return a + ba * fy, d0 + (d1 - d0) * fy, ba


class FreeGrid:
    """Where beams have passed: a coarse count of crossings per cell, grown as needed. A
    scan matched at the wrong place puts end points where the submap's own beams passed
    freely; at the right place its points fall on walls or in space never seen."""

    def __init__(self, resolution: float) -> None:
        self.resolution = resolution
        self.origin = np.zeros(2)
        self.counts: npt.NDArray[np.int32] = np.zeros((0, 0), dtype=np.int32)

    def _ensure(self, lo: Array, hi: Array) -> None:
        layout = self.layout(lo, hi)
        if layout is None:
            return
        new_lo, rows, cols = layout
        counts = np.zeros((rows, cols), dtype=np.int32)
        if self.counts.size:
            h, w = self.counts.shape
            di, dj = np.rint((self.origin - new_lo) / self.resolution).astype(int)
            counts[dj : dj + h, di : di + w] = self.counts
        self.origin = new_lo
        self.counts = counts

    def layout(self, lo: Array, hi: Array) -> tuple[Array, int, int] | None:
        """As :meth:`FieldGrid.layout`: the grid's new origin, rows and columns to hold
        ``[lo, hi]``, or None.

        Raises:
            GridLimitError: that takes more than :data:`GRID_CELLS` cells.
        """
        res = self.resolution
        h, w = self.counts.shape
        have_hi = self.origin + np.array([w, h]) * res
        if self.counts.size and np.all(lo >= self.origin) and np.all(hi < have_hi):
            return None
        margin = _GROW_MARGIN
        if self.counts.size:
            lo = np.minimum(lo, self.origin)
            hi = np.maximum(hi, have_hi)
            margin = max(margin, 0.25 * float(np.max(have_hi - self.origin)))
        return _layout(self.origin if self.counts.size else None, res, lo, hi, margin)

    def add_beams(self, sensor: Array, ends: Array, short: float) -> None:
        """Beams from ``sensor`` (2,) to ``ends`` (N, 2), all in the grid's frame, each
        counted up to ``short`` metres before its end."""
        if not len(ends):
            return
        d = ends - sensor
        length = np.hypot(d[:, 0], d[:, 1]) - short
        keep = length > 0
        d, length = d[keep], length[keep]
        if not len(d):
            return
        unit = d / (length + short)[:, None]
        steps = np.ceil(length / self.resolution).astype(np.int64)
        self._ensure(np.minimum(ends.min(axis=0), sensor), np.maximum(ends.max(axis=0), sensor))
        w = self.counts.shape[1]
        total = int(steps.sum())
        if total <= _BATCH_SAMPLES:
            flat = np.unique(self._cells(sensor, unit, steps, w))  # once per beam set is enough
            self.counts.reshape(-1)[flat] += 1
            return
        # A scan of many long beams: a batch of beams at a time, their cells marked once.
        crossed = np.zeros(self.counts.size, dtype=bool)
        for part in _batches(steps, _BATCH_SAMPLES):
            crossed[self._cells(sensor, unit[part], steps[part], w)] = True
        self.counts.reshape(-1)[crossed] += 1

    def _cells(
        self, sensor: Array, unit: Array, steps: npt.NDArray[np.int64], width: int
    ) -> npt.NDArray[np.int64]:
        """The flat cells of samples every cell along each beam (with repeats)."""
        ray = np.repeat(np.arange(len(steps)), steps)
        first = np.cumsum(steps) - steps
        t = (np.arange(int(steps.sum())) - first[ray]) * self.resolution
        pts = sensor + unit[ray] * t[:, None]
        ij = np.floor((pts - self.origin) / self.resolution).astype(np.int64)
        flat: npt.NDArray[np.int64] = ij[:, 1] * width + ij[:, 0]
        return flat

    def at(self, points: Array) -> npt.NDArray[np.int32]:
        """Crossing counts at points (N, 2) (0 off the grid)."""
        if not self.counts.size:
            return np.zeros(len(points), dtype=np.int32)
        ij = np.floor((points - self.origin) / self.resolution).astype(np.int64)
        h, w = self.counts.shape
        inside = (ij[:, 0] >= 0) & (ij[:, 1] >= 0) & (ij[:, 0] < w) & (ij[:, 1] < h)
        out = np.zeros(len(points), dtype=np.int32)
        out[inside] = self.counts[ij[inside, 1], ij[inside, 0]]
        return out
