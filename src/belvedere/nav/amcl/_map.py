"""The map as amcl reads it: each cell free, occupied or unknown, and the distance fields the
laser models look up.

Cell ``i`` covers ``[origin + i·res, origin + (i+1)·res)``, as map_server lays the map out.
amcl itself centres cell ``i`` at ``origin + i·res`` (its ``MAP_WXGX``/``MAP_GXWX`` macros),
which moves the whole map half a cell towards the origin and its estimates with it (2.5 cm in
x and y on a 5 cm map); here the cells are where the map says they are.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from belvedere.maps import OccupancyMap

__all__ = ["FREE", "OCCUPIED", "UNKNOWN", "AmclMap"]

FREE = -1
UNKNOWN = 0
OCCUPIED = 1

Float32s = npt.NDArray[np.float32]
Ints = npt.NDArray[np.int64]


@dataclass(eq=False)
class AmclMap:
    """``states[row, col]``: FREE, UNKNOWN or OCCUPIED (amcl's ``occ_state``)."""

    states: npt.NDArray[np.int8]
    resolution: float
    origin_x: float = 0.0
    origin_y: float = 0.0
    _occ_dist: dict[float, Float32s] = field(default_factory=dict, repr=False)
    _free_dist: Float32s | None = field(default=None, repr=False)
    _free_cells: Ints | None = field(default=None, repr=False)

    @classmethod
    def from_occupancy(cls, grid: OccupancyMap) -> AmclMap:
        """amcl's conversion: 0 is free, 100 occupied, anything else unknown (the origin's
        yaw is ignored, as amcl ignores it)."""
        data = np.asarray(grid.data)
        states = np.full(data.shape, UNKNOWN, dtype=np.int8)
        states[data == 0] = FREE
        states[data == 100] = OCCUPIED
        return cls(states, float(grid.resolution), float(grid.origin[0]), float(grid.origin[1]))

    @property
    def width(self) -> int:
        return int(self.states.shape[1])

    @property
    def height(self) -> int:
        return int(self.states.shape[0])

    def cell_of(
        self, x: npt.ArrayLike, y: npt.ArrayLike
    ) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
        """(col, row) of the cells holding points (may lie outside the map)."""
        col = np.floor((np.asarray(x) - self.origin_x) / self.resolution).astype(np.int64)
        row = np.floor((np.asarray(y) - self.origin_y) / self.resolution).astype(np.int64)
        return col, row

    def occ_dist(self, max_dist: float) -> Float32s:
        """Metres from each cell's centre to the nearest occupied cell's, at most
        ``max_dist`` (amcl's ``map_update_cspace``)."""
        cached = self._occ_dist.get(max_dist)
        if cached is None:
            occupied = self.states == OCCUPIED
            if occupied.any():
                dist = ndimage.distance_transform_edt(~occupied) * self.resolution
                cached = np.minimum(dist, max_dist).astype(np.float32)
            else:
                cached = np.full(self.states.shape, max_dist, dtype=np.float32)
            self._occ_dist = {max_dist: cached}
        return cached

    def free_dist(self) -> Float32s:
        """Cells from each cell's centre to the nearest cell a ray stops in (not free, or off
        the map), over the map with a one-cell border of such cells."""
        if self._free_dist is None:
            free = np.zeros((self.height + 2, self.width + 2), dtype=bool)
            free[1:-1, 1:-1] = self.states == FREE
            self._free_dist = ndimage.distance_transform_edt(free).astype(np.float32)
        return self._free_dist

    def free_cells(self) -> Ints:
        """(K, 2) the (col, row) of every free cell, where random poses are drawn."""
        if self._free_cells is None:
            rows, cols = np.nonzero(self.states == FREE)
            self._free_cells = np.stack([cols, rows], axis=1).astype(np.int64)
        return self._free_cells

    def random_poses(self, count: int, rng: np.random.Generator) -> npt.NDArray[np.float64]:
        """(count, 3) poses uniform over the free cells' centres, headings uniform in
        [-pi, pi) (amcl's ``uniformPoseGenerator``)."""
        cells = self.free_cells()
        if len(cells) == 0:
            msg = "the map has no free cell to place a particle in"
            raise ValueError(msg)
        pick = cells[rng.integers(0, len(cells), count)]
        out = np.empty((count, 3))
        out[:, 0] = self.origin_x + (pick[:, 0] + 0.5) * self.resolution
        out[:, 1] = self.origin_y + (pick[:, 1] + 0.5) * self.resolution
        out[:, 2] = rng.random(count) * 2.0 * np.pi - np.pi
        return out
