"""hector_mapping's SLAM: scan matching alone, no odometry.

The map is a pyramid of log-odds occupancy grids (``levels``, each half the resolution of the
one below). A scan's end points are matched against the map by Gauss-Newton on the bilinearly
interpolated occupancy — coarse levels first, each refining the last — starting from the
previous pose; the map is updated only after the robot moved ``distance_thresh`` or turned
``angle_thresh`` since the last update (hector's rule, so that noise does not smear walls).
Plain arrays in and out: the ``hector_mapping`` node wraps it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

__all__ = ["HectorParams", "HectorSlam", "LogOddsGrid"]

Array = npt.NDArray[np.float64]

_BATCH_SAMPLES = 1 << 22
"""Samples along rays placed at once when a scan updates the map (a memory bound)."""


def _log_odds(p: float) -> float:
    return math.log(p / (1.0 - p))


@dataclass(frozen=True)
class HectorParams:
    """hector_mapping's parameters (its names without the ``map_``/``laser_`` prefixes)."""

    resolution: float = 0.025
    size: int = 1024
    start_x: float = 0.5
    """Where the world origin lies in the map, as a fraction of its width."""
    start_y: float = 0.5
    levels: int = 3
    update_free: float = 0.4
    update_occupied: float = 0.9
    distance_thresh: float = 0.4
    angle_thresh: float = 0.9
    laser_min: float = 0.4
    laser_max: float = 30.0
    iterations: tuple[int, ...] = (5, 3)
    """Gauss-Newton iterations at the finest level, then at every coarser one."""


class LogOddsGrid:
    """One level: log-odds per cell; cell (i, j) covers x ∈ origin_x + [i, i+1)·res."""

    def __init__(self, resolution: float, size: int, origin: tuple[float, float]) -> None:
        self.resolution = resolution
        self.size = size
        self.origin = origin
        self.cells = np.zeros((size, size), dtype=np.float32)  # [row = y, column = x]

    def to_cells(self, xy: Array) -> Array:
        """World points (N, 2) in continuous cell coordinates (cell centres at +0.5)."""
        cells: Array = (xy - np.asarray(self.origin, dtype=np.float64)) / self.resolution
        return cells

    def probability(self) -> npt.NDArray[np.float32]:
        return (1.0 - 1.0 / (1.0 + np.exp(self.cells))).astype(np.float32)

    def sample(self, cells: Array) -> tuple[Array, Array]:
        """Interpolated occupancy probability at ``cells`` (N, 2) and its gradient per cell
        (N, 2); points off the map read as unknown (0.5) with no gradient."""
        x = cells[:, 0] - 0.5
        y = cells[:, 1] - 0.5
        x0 = np.floor(x).astype(np.int64)
        y0 = np.floor(y).astype(np.int64)
        inside = (x0 >= 0) & (y0 >= 0) & (x0 < self.size - 1) & (y0 < self.size - 1)
        value = np.full(len(cells), 0.5)
        gradient = np.zeros((len(cells), 2))
        if not inside.any():
            return value, gradient
        xi, yi = x0[inside], y0[inside]
        fx, fy = x[inside] - xi, y[inside] - yi
        grid = self.cells
        p00 = _prob(grid[yi, xi])
        p10 = _prob(grid[yi, xi + 1])
        p01 = _prob(grid[yi + 1, xi])
        p11 = _prob(grid[yi + 1, xi + 1])
        value[inside] = fy * (fx * p11 + (1 - fx) * p01) + (1 - fy) * (fx * p10 + (1 - fx) * p00)
        gradient[inside, 0] = fy * (p11 - p01) + (1 - fy) * (p10 - p00)
        gradient[inside, 1] = fx * (p11 - p10) + (1 - fx) * (p01 - p00)
        return value, gradient

    def update(
        self, origin_xy: tuple[float, float], ends: Array, free: float, occupied: float
    ) -> None:
        """Rays from ``origin_xy`` to each of ``ends`` (N, 2, world): cells passed are more
        likely free, end cells more likely occupied; each cell changes once per scan.

        Only the stretch of each ray over the map is sampled, a batch of rays at a time: the
        work is bounded by the map's size, not by how far the rays go."""
        if len(ends) == 0:
            return
        start = self.to_cells(np.asarray([origin_xy]))[0]
        stop = self.to_cells(ends)
        span = stop - start
        # half-cell samples along every ray, k / steps of the way for k in [0, steps)
        steps = np.maximum(np.ceil(np.abs(span).max(axis=1) * 2.0), 1.0)
        first, last = self._on_map(start, span, steps)
        # (a ray crosses the map in at most 2·√2·size half-cells: a bound whatever the floats)
        count = np.clip(last - first, 0, 3 * self.size + 4).astype(np.int64)
        size = self.size
        if int(count.sum()) <= _BATCH_SAMPLES:
            free_cells = np.unique(self._samples(start, span, steps, first, count))
        else:
            passed = np.zeros(size * size, dtype=bool)
            cum = np.cumsum(count)
            begin = 0
            while begin < len(count):
                end = max(begin + 1, int(np.searchsorted(cum, cum[begin] + _BATCH_SAMPLES)))
                part = slice(begin, end)
                passed[self._samples(start, span[part], steps[part], first[part], count[part])] = (
                    True
                )
                begin = end
            free_cells = np.flatnonzero(passed)
        ex = np.floor(stop[:, 0]).astype(np.int64)
        ey = np.floor(stop[:, 1]).astype(np.int64)
        on = (ex >= 0) & (ey >= 0) & (ex < size) & (ey < size)
        end_cells = np.unique(ey[on] * size + ex[on])
        free_cells = np.setdiff1d(free_cells, end_cells, assume_unique=True)
        flat = self.cells.reshape(-1)
        flat[free_cells] += free
        flat[end_cells] += occupied
        np.clip(flat, -50.0, 50.0, out=flat)

    def _on_map(self, start: Array, span: Array, steps: Array) -> tuple[Array, Array]:
        """For each ray, the samples ``k`` in ``[first, last)`` that can fall on the map
        (a superset: the rest of ``[0, steps)`` surely falls off it)."""
        lo = np.zeros(len(span))
        hi = np.ones(len(span))
        with np.errstate(divide="ignore", invalid="ignore"):
            for axis in (0, 1):
                d = span[:, axis]
                a = (0.0 - start[axis]) / d
                b = (self.size - start[axis]) / d
                flat = d == 0
                inside = 0.0 <= start[axis] < self.size
                lo = np.where(flat, lo if inside else 1.0, np.maximum(lo, np.minimum(a, b)))
                hi = np.where(flat, hi, np.minimum(hi, np.maximum(a, b)))
        first = np.clip(np.floor(lo * steps) - 1.0, 0.0, steps)
        last = np.clip(np.ceil(hi * steps) + 1.0, 0.0, steps)
        return first, np.where(hi < lo, first, last)

    def _samples(
        self,
        start: Array,
        span: Array,
        steps: Array,
        first: Array,
        count: npt.NDArray[np.int64],
    ) -> npt.NDArray[np.int64]:
        """The flat cells (on the map) of samples ``first .. first + count`` of each ray."""
        ray = np.repeat(np.arange(len(count)), count)
        offset = np.cumsum(count) - count
        k = first[ray] + (np.arange(int(count.sum())) - offset[ray])
        t = k / steps[ray]
        fx = np.floor(start[0] + span[ray, 0] * t).astype(np.int64)
        fy = np.floor(start[1] + span[ray, 1] * t).astype(np.int64)
        size = self.size
        on = (fx >= 0) & (fy >= 0) & (fx < size) & (fy < size)
        cells: npt.NDArray[np.int64] = fy[on] * size + fx[on]
        return cells


def _prob(log_odds: npt.NDArray[np.float32]) -> Array:
    return 1.0 - 1.0 / (1.0 + np.exp(log_odds.astype(np.float64)))


class HectorSlam:
    """The map pyramid and the pose of the scanner's base in it."""

    def __init__(self, params: HectorParams | None = None) -> None:
        self.params = params or HectorParams()
        p = self.params
        self.levels: list[LogOddsGrid] = []
        for level in range(p.levels):
            scale = 2**level
            size = max(2, p.size // scale)
            resolution = p.resolution * scale
            origin = (-p.start_x * size * resolution, -p.start_y * size * resolution)
            self.levels.append(LogOddsGrid(resolution, size, origin))
        self.pose = np.zeros(3)
        """x, y, yaw of the base in the map frame."""
        self._last_update: Array | None = None
        self.covariance = np.diag([0.01, 0.01, 0.01])
        self.updates = 0

    @property
    def map(self) -> LogOddsGrid:
        """The finest level (what ``/map`` shows)."""
        return self.levels[0]

    def process(self, points: Array, sensor_xy: tuple[float, float] = (0.0, 0.0)) -> Array:
        """Match one scan and update the map. ``points``: the scan's end points in the base
        frame (N, 2) — already cut to [laser_min, laser_max]; ``sensor_xy`` the laser's
        position in the base frame. Returns the new pose (x, y, yaw)."""
        p = self.params
        if len(points) == 0:
            return self.pose.copy()
        if self.updates > 0:
            self.pose = self._match(points)
        moved = self._last_update is None or (
            math.hypot(*(self.pose[:2] - self._last_update[:2])) > p.distance_thresh
            or abs(_wrap(self.pose[2] - self._last_update[2])) > p.angle_thresh
        )
        if moved:
            world = _transform(self.pose, points)
            sensor = _transform(self.pose, np.asarray([sensor_xy]))[0]
            free, occupied = _log_odds(p.update_free), _log_odds(p.update_occupied)
            for grid in self.levels:
                grid.update((float(sensor[0]), float(sensor[1])), world, free, occupied)
            self._last_update = self.pose.copy()
            self.updates += 1
        return self.pose.copy()

    def _match(self, points: Array) -> Array:
        pose = self.pose.copy()
        p = self.params
        for level in range(len(self.levels) - 1, -1, -1):
            grid = self.levels[level]
            count = p.iterations[0] if level == 0 else p.iterations[-1]
            for _ in range(count):
                step, hessian = _gauss_newton_step(grid, pose, points)
                if step is None:
                    break
                pose += step
                pose[2] = _wrap(pose[2])
            if level == 0 and hessian is not None:
                self.covariance = _covariance(hessian)
        return pose


def _gauss_newton_step(
    grid: LogOddsGrid, pose: Array, points: Array
) -> tuple[Array | None, Array | None]:
    cos, sin = math.cos(pose[2]), math.sin(pose[2])
    world = _transform(pose, points)
    value, gradient = grid.sample(grid.to_cells(world))
    gradient = gradient / grid.resolution  # per metre
    residual = 1.0 - value
    # d(world)/d(yaw) for each point
    dyaw_x = -sin * points[:, 0] - cos * points[:, 1]
    dyaw_y = cos * points[:, 0] - sin * points[:, 1]
    jacobian = np.column_stack(
        (gradient[:, 0], gradient[:, 1], gradient[:, 0] * dyaw_x + gradient[:, 1] * dyaw_y)
    )
    hessian = jacobian.T @ jacobian
    rhs = jacobian.T @ residual
    if not abs(np.linalg.det(hessian)) >= 1e-12:  # (NaN too)
        return None, None
    step = np.asarray(np.linalg.solve(hessian, rhs), dtype=np.float64)
    if not np.isfinite(step).all():
        return None, None
    return step, hessian


def _covariance(hessian: Array) -> Array:
    try:
        return np.asarray(np.linalg.inv(hessian), dtype=np.float64)
    except np.linalg.LinAlgError:
        return np.diag([1.0, 1.0, 1.0])


def _transform(pose: Array, points: Array) -> Array:
    cos, sin = math.cos(pose[2]), math.sin(pose[2])
    out = np.empty_like(points, dtype=np.float64)
    out[:, 0] = cos * points[:, 0] - sin * points[:, 1] + pose[0]
    out[:, 1] = sin * points[:, 0] + cos * points[:, 1] + pose[1]
    return out


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi
