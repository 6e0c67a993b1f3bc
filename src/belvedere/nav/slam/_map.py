"""The submap mapper's occupancy map: traced from its keyframes at their optimised poses with
GMapping's counting (:mod:`._occupancy`), within :data:`~belvedere.bounded.GRID_CELLS`.

:class:`MapDrawing` is mixed into :class:`~belvedere.nav.slam._slam.SubmapSlam`. A keyframe is
added only if the map's box, grown by its reach, stays within the cap (:meth:`_map_refusal`);
the map is traced a batch of keyframes at a time, so its memory does not grow with the beam
count.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from belvedere.bounded import GRID_CELLS
from belvedere.maps import OccupancyMap
from belvedere.nav._input import Tally
from belvedere.nav.slam._occupancy import OccupancyCounts
from belvedere.nav.slam._params import GMappingParams
from belvedere.nav.slam._types import LaserGeometry, _Keyframe

__all__ = ["MapDrawing"]

Array = npt.NDArray[np.float64]

_TRACE_BEAMS = 1 << 19
"""Beams traced into the map at once (the arrays of a batch take some 60 MiB)."""


class MapDrawing:
    """The occupancy map over the mapper's keyframes (the attributes below, set by it)."""

    params: GMappingParams
    laser: LaserGeometry
    resolution: float
    max_range: float
    max_urange: float
    keyframes: list[_Keyframe]
    tally: Tally
    _map: OccupancyCounts | None
    _map_poses: Array
    _map_partial: bool
    _map_lo: Array
    _map_hi: Array

    def keyframe_poses(self) -> Array:
        raise NotImplementedError  # the mapper's

    def _extent(self, ranges: Array) -> float:
        """How far from the base the beams :meth:`_trace` draws reach."""
        laser = self.laser
        with np.errstate(invalid="ignore"):
            valid = np.isfinite(ranges) & (ranges >= laser.range_min) & (ranges <= self.max_range)
        r = np.minimum(ranges[valid], self.max_urange)
        ends = laser.origin + laser.directions[valid] * r[:, None]
        far = float(np.hypot(ends[:, 0], ends[:, 1]).max()) if len(ends) else 0.0
        return max(far, float(np.hypot(*laser.origin)))

    def _map_refusal(self, pose: Array, extent: float) -> str | None:
        """Why a keyframe at ``pose`` reaching ``extent`` cannot be added to the map (it
        would pass :data:`GRID_CELLS`), or None."""
        lo = np.minimum(self._map_lo, pose[:2] - extent)
        hi = np.maximum(self._map_hi, pose[:2] + extent)
        cells = OccupancyCounts.cells_for(self.resolution, lo, hi)
        if not cells <= GRID_CELLS:
            return f"the map to {cells:,.0f} cells"
        return None

    def _grow_map_box(self, pose: Array, extent: float) -> None:
        self._map_lo = np.minimum(self._map_lo, pose[:2] - extent)
        self._map_hi = np.maximum(self._map_hi, pose[:2] + extent)

    def occupancy(self) -> OccupancyMap:
        """The occupancy grid traced from every keyframe at its current pose (keyframes
        already traced at the same pose are not traced again), a batch of keyframes at a
        time (a bound on memory, whatever the beam count).

        Each keyframe was added only if the map's box stayed within :data:`GRID_CELLS`;
        should loop closures have moved some since past that (hostile odometry), those are
        left out of this map (counted)."""
        p = self.params
        poses = self.keyframe_poses()
        keyframes = self.keyframes
        kept = self._within_cap(poses)
        done = len(self._map_poses)
        if (
            self._map is None
            or kept is not None
            or self._map_partial
            or done > len(poses)
            or (done and np.abs(poses[:done] - self._map_poses).max() > 1e-9)
        ):
            self._map = OccupancyCounts(self.resolution, p.xmin, p.ymin, p.xmax, p.ymax)
            done = 0
        self._map_partial = kept is not None
        if kept is not None:
            keyframes = [kf for kf, keep in zip(keyframes, kept, strict=True) if keep]
            poses = poses[kept]
        batch = max(1, _TRACE_BEAMS // max(len(self.laser.directions), 1))
        for start in range(done, len(poses), batch):
            end = start + batch
            self._trace(self._map, poses[start:end], keyframes[start:end])
        self._map_poses = poses
        return self._map.to_map(p.occ_thresh)

    def _within_cap(self, poses: Array) -> npt.NDArray[np.bool_] | None:
        """None when the keyframes at ``poses`` fit a map within :data:`GRID_CELLS`; else
        which of them lie within the box they were added in (counted)."""
        if not len(poses):
            return None
        extent = np.array([kf.extent for kf in self.keyframes])[:, None]
        lo = np.minimum((poses[:, :2] - extent).min(axis=0), [self.params.xmin, self.params.ymin])
        hi = np.maximum((poses[:, :2] + extent).max(axis=0), [self.params.xmax, self.params.ymax])
        if OccupancyCounts.cells_for(self.resolution, lo, hi) <= GRID_CELLS:
            return None
        kept: npt.NDArray[np.bool_] = np.all(
            (poses[:, :2] - extent >= self._map_lo) & (poses[:, :2] + extent <= self._map_hi),
            axis=1,
        )
        self.tally.add(
            "left {items} out of {count}: loop closures moved them past the map's cap of "
            f"{GRID_CELLS:,} cells",
            noun="map",
            items=int(np.count_nonzero(~kept)),
            item="keyframe",
        )
        return kept

    def _trace(self, counts: OccupancyCounts, poses: Array, keyframes: list[_Keyframe]) -> None:
        laser = self.laser
        ranges = np.stack([kf.ranges for kf in keyframes]).astype(np.float64)
        with np.errstate(invalid="ignore"):
            valid = np.isfinite(ranges) & (ranges >= laser.range_min) & (ranges <= self.max_range)
        hit = valid & (ranges < self.max_urange)
        r = np.where(valid, np.minimum(ranges, self.max_urange), 0.0)
        c = np.cos(poses[:, 2])[:, None]
        s = np.sin(poses[:, 2])[:, None]
        ox = laser.origin[0]
        oy = laser.origin[1]
        sensors = np.stack(
            [poses[:, 0] + c[:, 0] * ox - s[:, 0] * oy, poses[:, 1] + s[:, 0] * ox + c[:, 0] * oy],
            axis=1,
        )
        dx = laser.directions[None, :, 0] * r
        dy = laser.directions[None, :, 1] * r
        ex = sensors[:, 0:1] + c * dx - s * dy
        ey = sensors[:, 1:2] + s * dx + c * dy
        keep = valid.reshape(-1)
        ends = np.stack([ex.reshape(-1), ey.reshape(-1)], axis=1)
        starts_idx = np.repeat(np.arange(len(poses)), ranges.shape[1])[keep]
        counts.add_scans_indexed(sensors, starts_idx, ends[keep], hit.reshape(-1)[keep])
