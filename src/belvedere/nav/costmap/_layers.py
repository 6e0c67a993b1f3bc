"""costmap_2d's layers over numpy grids: static, obstacle (with its observation buffers) and
inflation. Each layer writes into the master grid in plugin order."""

from __future__ import annotations

import logging
import math
from collections import deque
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from belvedere.nav.costmap._grid import FREE, INSCRIBED, LETHAL, NO_INFORMATION, CostGrid
from belvedere.nav.costmap._params import (
    InflationParams,
    ObstacleParams,
    SourceParams,
    StaticParams,
)
from belvedere.nav.costmap._raster import convex_fill, raytrace

__all__ = [
    "Bounds",
    "InflationLayer",
    "Observation",
    "ObstacleLayer",
    "StaticLayer",
    "inflation_cost",
    "union",
]

logger = logging.getLogger(__name__)

Costs = npt.NDArray[np.uint8]
Pose2D = tuple[float, float, float]
Bounds = tuple[int, int, int, int] | None
"""Cells a layer touched: columns i0 <= i < i1 and rows j0 <= j < j1 (None: none)."""
Window = tuple[slice, slice]
"""The part of the grid an update rewrites: (rows, columns)."""

_RAY_CELLS = 1 << 22
"""Cells of rays traced at once when clearing (a memory bound)."""


def _bounds(cols: npt.NDArray[np.int64], rows: npt.NDArray[np.int64]) -> Bounds:
    if cols.size == 0:
        return None
    return int(cols.min()), int(rows.min()), int(cols.max()) + 1, int(rows.max()) + 1


def whole(grid: CostGrid) -> Window:
    return slice(0, grid.height), slice(0, grid.width)


def union(a: Bounds, b: Bounds) -> Bounds:
    """The box around both (``updateBounds``' growing min/max)."""
    if a is None:
        return b
    if b is None:
        return a
    return min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3])


def _cell_distance(world: float, resolution: float) -> int:
    """costmap_2d's ``cellDistance``: a length in whole cells, rounded up."""
    return max(0, math.ceil(world / resolution))


def inflation_cost(
    distance_cells: npt.NDArray[np.float64],
    resolution: float,
    inscribed_radius: float,
    cost_scaling_factor: float,
) -> Costs:
    """The inflation layer's cost at a distance (in cells) from the nearest lethal cell:
    lethal on it, inscribed within the inscribed radius, else
    ``(INSCRIBED - 1) · exp(-cost_scaling_factor · (d·resolution - inscribed_radius))``
    truncated to an integer."""
    metres = distance_cells * resolution
    with np.errstate(over="ignore"):
        decay = (INSCRIBED - 1) * np.exp(-cost_scaling_factor * (metres - inscribed_radius))
    cost = np.where(metres <= inscribed_radius, INSCRIBED, np.floor(decay))
    cost = np.where(distance_cells == 0, LETHAL, cost)
    return np.clip(cost, 0, 255).astype(np.uint8)


def clear_area(grid: CostGrid, x: float, y: float, size: float, *, invert: bool) -> None:
    """``ClearCostmapRecovery``'s ``clearMap``: every cell outside the open square of side
    ``size`` centred on (x, y) (inside it, with ``invert``) back to NO_INFORMATION. The
    square's corners become cells by truncation toward zero (``worldToMapNoBounds``), and the
    cells on its edge are cleared too."""
    res = grid.resolution
    i0 = int((x - size / 2 - grid.origin_x) / res)
    j0 = int((y - size / 2 - grid.origin_y) / res)
    i1 = int((x + size / 2 - grid.origin_x) / res)
    j1 = int((y + size / 2 - grid.origin_y) / res)
    inside = np.zeros(grid.costs.shape, dtype=bool)
    cols = slice(max(i0 + 1, 0), max(i1, 0))
    rows = slice(max(j0 + 1, 0), max(j1, 0))
    inside[rows, cols] = True
    grid.costs[inside == invert] = NO_INFORMATION


@dataclass(frozen=True)
class Observation:
    """Points seen by one sensor reading, in the costmap's global frame: the sensor's origin
    (x, y, z), the points (N, 3) and the reading's stamp."""

    origin: npt.NDArray[np.float64]
    points: npt.NDArray[np.float64]
    stamp_ns: int


class StaticLayer:
    """The map from map_server as costs (``interpretValue``): unknown as NO_INFORMATION when
    tracking unknown space (else free), values at or above ``lethal_cost_threshold`` lethal,
    the rest free (``trinary_costmap``) or scaled to ``value/threshold·LETHAL``."""

    def __init__(self, params: StaticParams) -> None:
        self.params = params
        self.map: CostGrid | None = None
        self.frame = ""
        self.received = 0

    def interpret(self, data: npt.NDArray[np.int8]) -> Costs:
        p = self.params
        value = data.astype(np.int8).view(np.uint8)
        unknown = np.uint8(p.unknown_cost_value & 0xFF)
        threshold = p.lethal_cost_threshold
        scaled = (value.astype(np.float64) / threshold * LETHAL).astype(np.uint8)
        out = np.where(value >= threshold, LETHAL, FREE if p.trinary_costmap else scaled)
        is_unknown = value == unknown
        out = np.where(is_unknown, NO_INFORMATION if p.track_unknown_space else FREE, out)
        return out.astype(np.uint8)

    def set_map(
        self, data: npt.NDArray[np.int8], resolution: float, origin: tuple[float, float], frame: str
    ) -> bool:
        """Take a map (rows from the bottom, as OccupancyGrid lays them out); False when
        ``first_map_only`` keeps the first."""
        if self.params.first_map_only and self.received:
            return False
        self.map = CostGrid(self.interpret(data), resolution, origin[0], origin[1])
        self.frame = frame
        self.received += 1
        return True

    def clear_area(self, x: float, y: float, size: float, *, invert: bool = False) -> None:
        """``ClearCostmapRecovery`` on the layer's copy of the map (until the next map)."""
        if self.map is not None:
            clear_area(self.map, x, y, size, invert=invert)

    def update(
        self,
        master: CostGrid,
        map_to_global: Pose2D | None,
        rolling: bool,
        window: Window | None = None,
    ) -> None:
        """Write the map into the master's ``window`` (all by default; a rolling window: all
        of it, sampled through ``map_to_global``)."""
        if self.map is None or not self.params.enabled:
            return
        window = window or whole(master)
        if rolling:
            source, valid = self._sample(master, map_to_global or (0.0, 0.0, 0.0))
            if self.params.use_maximum:
                master.costs[valid] = _maximum(master.costs[valid], source[valid])
            else:
                master.costs[valid] = source[valid]
            return
        if self.map.costs.shape != master.costs.shape:
            return
        source = self.map.costs[window]
        if self.params.use_maximum:
            master.costs[window] = _maximum(master.costs[window], source)
        else:
            master.costs[window] = source

    def _sample(
        self, master: CostGrid, map_to_global: Pose2D
    ) -> tuple[Costs, npt.NDArray[np.bool_]]:
        """The map's cost under each master cell's centre (a rolling window in another frame)."""
        assert self.map is not None
        rows, cols = np.mgrid[0 : master.height, 0 : master.width]
        wx = master.origin_x + (cols + 0.5) * master.resolution
        wy = master.origin_y + (rows + 0.5) * master.resolution
        tx, ty, yaw = map_to_global
        c, s = math.cos(yaw), math.sin(yaw)
        mx = c * (wx - tx) + s * (wy - ty)
        my = -s * (wx - tx) + c * (wy - ty)
        i = np.floor((mx - self.map.origin_x) / self.map.resolution).astype(np.int64)
        j = np.floor((my - self.map.origin_y) / self.map.resolution).astype(np.int64)
        valid = (i >= 0) & (i < self.map.width) & (j >= 0) & (j < self.map.height)
        out = np.zeros_like(master.costs)
        out[valid] = self.map.costs[j[valid], i[valid]]
        return out, valid


def _maximum(old: Costs, new: Costs) -> Costs:
    """costmap_2d's ``updateWithMax``: unknown in the layer leaves the master alone; unknown in
    the master takes the layer's value."""
    take = (new != NO_INFORMATION) & ((old == NO_INFORMATION) | (old < new))
    return np.where(take, new, old).astype(np.uint8)


class _Buffer:
    """An ``ObservationBuffer``: the readings of one source, kept for its persistence."""

    def __init__(self, params: SourceParams) -> None:
        self.params = params
        self.observations: deque[Observation] = deque()
        self.last_ns: int | None = None

    def add(self, observation: Observation, now_ns: int) -> None:
        p = self.params
        z = observation.points[:, 2]
        keep = (z >= p.min_obstacle_height) & (z <= p.max_obstacle_height)
        self.observations.appendleft(
            Observation(observation.origin, observation.points[keep], observation.stamp_ns)
        )
        self.last_ns = now_ns
        self.purge(now_ns)

    def purge(self, now_ns: int) -> None:
        keep_ns = round(self.params.observation_persistence * 1e9)
        if keep_ns == 0:
            while len(self.observations) > 1:
                self.observations.pop()
            return
        while self.observations and now_ns - self.observations[-1].stamp_ns > keep_ns:
            self.observations.pop()

    def current(self, now_ns: int) -> bool:
        rate = self.params.expected_update_rate
        if rate == 0:
            return True
        return self.last_ns is not None and now_ns - self.last_ns <= round(rate * 1e9)


class ObstacleLayer:
    """Marks lethal cells where sensors see points (closer than ``obstacle_range``, below
    ``max_obstacle_height``) and clears the cells rays pass through (up to
    ``raytrace_range``); clears under the footprint; combines by overwrite or maximum."""

    def __init__(self, params: ObstacleParams) -> None:
        self.params = params
        self.default = NO_INFORMATION if params.track_unknown_space else FREE
        self.buffers = {source.name: _Buffer(source) for source in params.sources}
        self.grid: CostGrid | None = None
        self._warned: set[str] = set()

    def match(self, master: CostGrid) -> None:
        """Take the master's size and place, keeping what overlaps (``updateOrigin``)."""
        old = self.grid
        fresh = np.full_like(master.costs, self.default)
        if old is not None and old.resolution == master.resolution:
            di = round((master.origin_x - old.origin_x) / master.resolution)
            dj = round((master.origin_y - old.origin_y) / master.resolution)
            src_i = slice(max(di, 0), min(old.width, master.width + di))
            src_j = slice(max(dj, 0), min(old.height, master.height + dj))
            dst_i = slice(max(-di, 0), max(-di, 0) + max(0, src_i.stop - src_i.start))
            dst_j = slice(max(-dj, 0), max(-dj, 0) + max(0, src_j.stop - src_j.start))
            if src_i.stop > src_i.start and src_j.stop > src_j.start:
                fresh[dst_j, dst_i] = old.costs[src_j, src_i]
        self.grid = CostGrid(fresh, master.resolution, master.origin_x, master.origin_y)

    def add(self, source: str, observation: Observation, now_ns: int) -> None:
        self.buffers[source].add(observation, now_ns)

    def current(self, now_ns: int) -> bool:
        return all(buffer.current(now_ns) for buffer in self.buffers.values())

    def reset(self) -> None:
        if self.grid is not None:
            self.grid.costs[:] = self.default

    def clear_area(self, x: float, y: float, size: float, *, invert: bool = False) -> None:
        """``ClearCostmapRecovery`` on this layer (see :func:`clear_area`)."""
        if self.grid is not None:
            clear_area(self.grid, x, y, size, invert=invert)

    def update_bounds(
        self, now_ns: int, footprint_world: npt.NDArray[np.float64] | None = None
    ) -> Bounds:
        """Ray-trace the clearing observations, mark the marking ones, then clear the cells
        under the footprint; the box of the cells this touched."""
        grid = self.grid
        if grid is None or not self.params.enabled:
            return None
        touched: Bounds = None
        for buffer in self.buffers.values():
            buffer.purge(now_ns)
        for buffer in self.buffers.values():
            if buffer.params.clearing:
                for observation in buffer.observations:
                    touched = union(
                        touched, self._clear(grid, observation, buffer.params.raytrace_range)
                    )
        for buffer in self.buffers.values():
            if buffer.params.marking:
                for observation in buffer.observations:
                    touched = union(
                        touched, self._mark(grid, observation, buffer.params.obstacle_range)
                    )
        if self.params.footprint_clearing_enabled and footprint_world is not None:
            vertices = np.floor(
                (footprint_world - [grid.origin_x, grid.origin_y]) / grid.resolution
            ).astype(np.int64)
            cols, rows = convex_fill(vertices, grid.width, grid.height)
            grid.costs[rows, cols] = FREE
            touched = union(touched, _bounds(cols, rows))
        return touched

    def _mark(self, grid: CostGrid, observation: Observation, obstacle_range: float) -> Bounds:
        points = observation.points
        points = points[points[:, 2] <= self.params.max_obstacle_height]
        sq = ((points - observation.origin) ** 2).sum(axis=1)
        points = points[sq < obstacle_range**2]
        i = np.floor((points[:, 0] - grid.origin_x) / grid.resolution).astype(np.int64)
        j = np.floor((points[:, 1] - grid.origin_y) / grid.resolution).astype(np.int64)
        inside = (i >= 0) & (i < grid.width) & (j >= 0) & (j < grid.height)
        grid.costs[j[inside], i[inside]] = LETHAL
        return _bounds(i[inside], j[inside])

    def _clear(self, grid: CostGrid, observation: Observation, raytrace_range: float) -> Bounds:
        ox, oy = float(observation.origin[0]), float(observation.origin[1])
        start = grid.world_to_map(ox, oy)
        if start is None:
            if "origin" not in self._warned:
                self._warned.add("origin")
                logger.warning(
                    "the origin for the sensor at (%.2f, %.2f) is out of map bounds, so the "
                    "costmap cannot raytrace for it",
                    ox,
                    oy,
                )
            return None
        if len(observation.points) == 0:
            return None
        wx = observation.points[:, 0].copy()
        wy = observation.points[:, 1].copy()
        x_lo, y_lo = grid.origin_x, grid.origin_y
        x_hi = x_lo + grid.width * grid.resolution
        y_hi = y_lo + grid.height * grid.resolution
        # points off the map are pulled back along their ray to its edge, as costmap_2d does
        with np.errstate(divide="ignore", invalid="ignore"):
            for low, coord, other, o_c, o_o in ((x_lo, wx, wy, ox, oy), (y_lo, wy, wx, oy, ox)):
                out = coord < low
                t = (low - o_c) / (coord[out] - o_c)
                other[out] = o_o + (other[out] - o_o) * t
                coord[out] = low
            for high, coord, other, o_c, o_o in ((x_hi, wx, wy, ox, oy), (y_hi, wy, wx, oy, ox)):
                out = coord > high
                t = (high - o_c) / (coord[out] - o_c)
                other[out] = o_o + (other[out] - o_o) * t
                coord[out] = high - 0.001
        i = np.floor((wx - x_lo) / grid.resolution).astype(np.int64)
        j = np.floor((wy - y_lo) / grid.resolution).astype(np.int64)
        inside = (i >= 0) & (i < grid.width) & (j >= 0) & (j < grid.height)
        ends = np.column_stack([i[inside], j[inside]])
        reach = _cell_distance(raytrace_range, grid.resolution)
        # A batch of rays at a time: each is at most the grid's width or height long, which
        # times 65,536 beams of a long raytrace_range would not fit in memory at once.
        batch = max(1, _RAY_CELLS // (min(reach, max(grid.width, grid.height)) + 2))
        touched: Bounds = None
        for first in range(0, len(ends), batch):
            cols, rows = raytrace(start[0], start[1], ends[first : first + batch], reach)
            ok = (cols >= 0) & (cols < grid.width) & (rows >= 0) & (rows < grid.height)
            grid.costs[rows[ok], cols[ok]] = FREE
            touched = union(touched, _bounds(cols[ok], rows[ok]))
        return touched

    def update(self, master: CostGrid, window: Window | None = None) -> None:
        """Write this layer's cells of ``window`` (all by default) into the master."""
        grid = self.grid
        if grid is None or not self.params.enabled:
            return
        window = window or whole(master)
        mine, theirs = grid.costs[window], master.costs[window]
        if self.params.combination_method == 0:
            known = mine != NO_INFORMATION
            theirs[known] = mine[known]
        else:
            theirs[:] = _maximum(theirs, mine)


class InflationLayer:
    """Costs that fall off with the distance to the nearest lethal cell (see
    :func:`inflation_cost`), out to ``inflation_radius`` (in whole cells, rounded up)."""

    def __init__(self, params: InflationParams) -> None:
        self.params = params

    def reach(self, resolution: float) -> int:
        """How many cells a change of a lethal cell can move inflated costs."""
        return _cell_distance(self.params.inflation_radius, resolution) + 1

    def update(
        self, master: CostGrid, inscribed_radius: float, window: Window | None = None
    ) -> None:
        """Inflate the lethal cells into the master's ``window`` (all of it by default;
        lethal cells up to the inflation radius outside it count too)."""
        p = self.params
        if not p.enabled:
            return
        window = window or whole(master)
        rows, cols = window
        pad = self.reach(master.resolution)
        r0, r1 = max(rows.start - pad, 0), min(rows.stop + pad, master.height)
        c0, c1 = max(cols.start - pad, 0), min(cols.stop + pad, master.width)
        lethal = master.costs[r0:r1, c0:c1] == LETHAL
        if not lethal.any():
            return
        inner = (slice(rows.start - r0, rows.stop - r0), slice(cols.start - c0, cols.stop - c0))
        distance = ndimage.distance_transform_edt(~lethal)[inner]
        reach = distance <= _cell_distance(p.inflation_radius, master.resolution)
        cost = inflation_cost(
            distance[reach], master.resolution, inscribed_radius, p.cost_scaling_factor
        )
        target = master.costs[window]
        old = target[reach]
        unknown = old == NO_INFORMATION
        replace = cost > FREE if p.inflate_unknown else cost >= INSCRIBED
        target[reach] = np.where(unknown, np.where(replace, cost, old), np.maximum(old, cost))
