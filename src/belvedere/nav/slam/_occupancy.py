"""The occupancy map built from scans at known poses, with GMapping's counting: every cell a
beam crosses is visited, the cell of its end point (if nearer than the usable range) also hit;
a cell's occupancy is hits / visits, unknown if never visited.

Beams are traced between cell centres by stepping along the longer axis and rounding the
other (Bresenham's cells for all but rare ties), all beams of a batch of scans at once.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from belvedere.bounded import GRID_CELLS, LimitError
from belvedere.maps import OccupancyMap

__all__ = ["OccupancyCounts"]

Array = npt.NDArray[np.float64]

_BATCH_CELLS = 4_000_000
"""Cells traced per batch (memory bound)."""


class OccupancyCounts:
    """Visit and hit counts over a grid that grows (by whole cells, keeping the cell
    boundaries of ``xmin``, ``ymin``) to hold every traced beam."""

    def __init__(self, resolution: float, xmin: float, ymin: float, xmax: float, ymax: float):
        self.resolution = resolution
        self.origin = np.array([xmin, ymin], dtype=np.float64)
        cols = max(1, math.ceil((xmax - xmin) / resolution))
        rows = max(1, math.ceil((ymax - ymin) / resolution))
        if rows * cols > GRID_CELLS:
            message = f"a map of {rows * cols:,} cells, more than the cap of {GRID_CELLS:,}"
            raise LimitError(message)
        self.visits = np.zeros((rows, cols), dtype=np.int32)
        self.hits = np.zeros((rows, cols), dtype=np.int32)

    @staticmethod
    def cells_for(resolution: float, lo: Array, hi: Array) -> float:
        """At most how many cells a map holding ``[lo, hi]`` has (as it grows by whole cells
        from wherever it began inside that box)."""
        size = np.ceil((hi - lo) / resolution) + 3
        return float(size[0] * size[1])

    def _grow(self, lo: Array, hi: Array) -> None:
        res = self.resolution
        rows, cols = self.visits.shape
        have_hi = self.origin + np.array([cols, rows]) * res
        if np.all(lo >= self.origin) and np.all(hi < have_hi):
            return
        extra_lo = np.maximum(np.ceil((self.origin - lo) / res), 0)
        extra_hi = np.maximum(np.ceil((hi - have_hi) / res) + 1, 0)
        cells = float((rows + extra_lo[1] + extra_hi[1]) * (cols + extra_lo[0] + extra_hi[0]))
        if not cells <= GRID_CELLS:  # (NaN too)
            message = f"a map of {cells:,.0f} cells, more than the cap of {GRID_CELLS:,}"
            raise LimitError(message)
        extra_lo = extra_lo.astype(int)
        extra_hi = extra_hi.astype(int)
        pad = ((int(extra_lo[1]), int(extra_hi[1])), (int(extra_lo[0]), int(extra_hi[0])))
        self.visits = np.pad(self.visits, pad)
        self.hits = np.pad(self.hits, pad)
        self.origin = self.origin - extra_lo * res

    def add_scans_indexed(
        self,
        sensors: Array,
        sensor_of: npt.NDArray[np.int64],
        ends: Array,
        hit: npt.NDArray[np.bool_],
    ) -> None:
        """Trace beams: ``sensors`` (S, 2) the sensor's world position per scan, and per
        beam the scan it belongs to (``sensor_of``), its end point (``ends``, (N, 2)) and
        whether the end is an obstacle (``hit``)."""
        if not len(ends):
            return
        starts = sensors[sensor_of]
        lo = np.minimum(ends.min(axis=0), sensors.min(axis=0))
        hi = np.maximum(ends.max(axis=0), sensors.max(axis=0))
        self._grow(lo, hi)
        res = self.resolution
        a = np.floor((starts - self.origin) / res).astype(np.int64)
        b = np.floor((ends - self.origin) / res).astype(np.int64)
        steps = np.abs(b - a).max(axis=1)
        width = self.visits.shape[1]
        visits = self.visits.reshape(-1)
        begin = 0
        while begin < len(steps):
            cum = np.cumsum(steps[begin:])
            end = begin + max(1, int(np.searchsorted(cum, _BATCH_CELLS)))
            self._trace(a[begin:end], b[begin:end], steps[begin:end], width, visits)
            begin = end
        cells = b[hit]
        flat = cells[:, 1] * width + cells[:, 0]
        counts = np.bincount(flat, minlength=len(visits)).astype(np.int32)
        self.hits.reshape(-1)[:] += counts
        visits += counts

    @staticmethod
    def _trace(
        a: npt.NDArray[np.int64],
        b: npt.NDArray[np.int64],
        steps: npt.NDArray[np.int64],
        width: int,
        visits: npt.NDArray[np.int32],
    ) -> None:
        # Every cell from a up to, not including, b (the end cell is counted apart).
        total = int(steps.sum())
        if not total:
            return
        ray = np.repeat(np.arange(len(steps)), steps)
        first = np.cumsum(steps) - steps
        k = np.arange(total) - first[ray]
        frac = k / np.maximum(steps[ray], 1)
        d = (b - a)[ray]
        x = a[ray, 0] + np.floor(d[:, 0] * frac + 0.5).astype(np.int64)
        y = a[ray, 1] + np.floor(d[:, 1] * frac + 0.5).astype(np.int64)
        visits += np.bincount(y * width + x, minlength=len(visits)).astype(np.int32)

    def to_map(self, occ_thresh: float) -> OccupancyMap:
        data = np.full(self.visits.shape, -1, dtype=np.int8)
        seen = self.visits > 0
        occ = np.zeros(self.visits.shape)
        occ[seen] = self.hits[seen] / self.visits[seen]
        data[seen] = np.where(occ[seen] > occ_thresh, 100, 0)
        return OccupancyMap(
            data, self.resolution, (float(self.origin[0]), float(self.origin[1]), 0.0)
        )
