"""2D laser SLAM with submaps and a pose graph, fed the inputs of slam_gmapping.

Why not GMapping's particle filter: on the benchmark logs of Kümmerle et al. (2009) graph
mapping beats the Rao-Blackwellized filter in accuracy, and it does with one trajectory what
the filter needs dozens of copies of the map for — in numpy, that is the difference between
seconds and minutes. The design follows Cartographer's 2D mapper in miniature:

* **Local matching.** Every scan is matched (:func:`refine`: Gauss-Newton on a likelihood
  field, pulled towards the odometry's prediction by the odometry error model) against the
  older of two overlapping *submaps*; so the trajectory has one accurate pose per scan, not
  only at map updates.
* **Keyframes.** After the robot travelled ``linearUpdate``, turned ``angularUpdate`` or
  waited ``temporalUpdate``, the scan is inserted into both active submaps. A submap is
  finished once it holds ``submap_keyframes`` of them; a new one begins half-way.
* **Loop closure.** Each keyframe is searched for (branch and bound, :mod:`._search`) in the
  finished submaps near its estimated pose, within a window that grows with the distance
  travelled since the last closure; a match that scores well enough becomes an edge of the
  pose graph (one node per submap), which is then optimised (:mod:`._posegraph`).
* **Map.** The occupancy grid is traced from the keyframes at their optimised poses, with
  GMapping's counting (:mod:`._occupancy`).

* **Input** is data (:mod:`belvedere.nav._input`): no grid passes ``GRID_CELLS`` (a keyframe
  that would grow one is left out of the map), bad odometry skips a scan (counted).

Plain arrays in, plain arrays out; deterministic (no random numbers at all).
"""

from __future__ import annotations

import contextlib
import logging
import math

import numpy as np
import numpy.typing as npt

from belvedere.bounded import GRID_CELLS
from belvedere.nav._input import Tally, grid_reach, pose_problem
from belvedere.nav.slam._grid import FieldGrid, FreeGrid, GridLimitError
from belvedere.nav.slam._loops import LoopClosing
from belvedere.nav.slam._map import MapDrawing
from belvedere.nav.slam._match import Match, refine
from belvedere.nav.slam._occupancy import OccupancyCounts
from belvedere.nav.slam._params import GMappingParams
from belvedere.nav.slam._posegraph import PoseGraph
from belvedere.nav.slam._proposal import sampled_covariance
from belvedere.nav.slam._se2 import between, compose, inverse, transform_points
from belvedere.nav.slam._search import SearchPyramid
from belvedere.nav.slam._types import (
    LaserGeometry,
    ScanPose,
    Tuning,
    _Closure,
    _Keyframe,
    _LastMatch,
    _State,
    _Submap,
)

__all__ = ["LaserGeometry", "ScanPose", "SubmapSlam", "Tuning"]

logger = logging.getLogger("belvedere.nav.slam")

Array = npt.NDArray[np.float64]


class SubmapSlam(LoopClosing, MapDrawing):
    """Feed :meth:`add_scan` with each scan's ranges and the base's odometry pose; read
    :meth:`pose`, :meth:`trajectory`, :meth:`occupancy`."""

    def __init__(
        self,
        laser: LaserGeometry,
        params: GMappingParams | None = None,
        tuning: Tuning | None = None,
        *,
        tally: Tally | None = None,
    ) -> None:
        self.params = params = params or GMappingParams()
        self.tuning = tuning = tuning or Tuning()
        self.tally = tally if tally is not None else Tally("slam", logger)
        """Where scans and keyframes left out are counted (see :mod:`belvedere.nav._input`)."""
        self.laser = laser.checked()
        self.max_range = params.maxRange if params.maxRange is not None else laser.range_max - 0.01
        self.max_urange = params.maxUrange if params.maxUrange is not None else self.max_range
        self.max_range, self.max_urange = max(self.max_range, 0.0), max(self.max_urange, 0.0)
        self.resolution = params.delta
        sigma = tuning.field_sigma if tuning.field_sigma is not None else params.sigma
        radius = tuning.field_radius if tuning.field_radius is not None else params.kernelSize + 2
        self._field = (sigma, radius)
        reach = grid_reach(self.resolution, radius + 2)
        if max(self.max_range, self.max_urange) > reach:
            # A beam longer than a grid of GRID_CELLS cells can hold is no use to any grid
            # (range_max 1e30 in a downloaded bag). Shorter beams are unaffected.
            self.tally.once(
                f"uses ranges up to {reach:.0f} m, the most a grid of {GRID_CELLS:,} cells at "
                f"{self.resolution:g} m holds around the laser (its range_max is "
                f"{laser.range_max:g} m)"
            )
            self.max_range = min(self.max_range, reach)
            self.max_urange = min(self.max_urange, reach)
        self.submaps: list[_Submap] = []
        self.keyframes: list[_Keyframe] = []
        self.graph = PoseGraph()
        self._active: list[int] = []
        self._local = np.zeros(3)
        self._last_odom: Array | None = None
        self._last_stamp = -math.inf
        self._since_linear = 0.0
        self._since_angular = 0.0
        self._last_keyframe_stamp = -math.inf
        self._kf_xy = np.zeros((0, 2))
        self._kf_submaps: list[int] = []
        self._state = _State()
        self.loop_closures = 0
        self.refused_closures = 0
        """Closures the scans agreed on that the graph refused: too far from it after
        optimising (``loop_max_error``) or beyond its Mahalanobis gate (``loop_max_chi2``)."""
        self._last_score = 1.0
        self._last_match: _LastMatch | None = None
        self._pending: list[_Closure] = []
        self._travel = 0.0
        self._map: OccupancyCounts | None = None
        self._map_poses = np.zeros((0, 3))
        self._map_partial = False
        """Whether the map was traced from some keyframes only (retraced in full next)."""
        self._map_lo = np.array([params.xmin, params.ymin], dtype=np.float64)
        self._map_hi = np.array([params.xmax, params.ymax], dtype=np.float64)
        """The box the map may grow to: its keyframes' reach around their poses when they
        were added (each added only if the box stays within :data:`GRID_CELLS`)."""

    # ------------------------------------------------------------------ scans

    def _points(self, ranges: Array) -> tuple[Array, npt.NDArray[np.bool_]]:
        """End points (base frame) of the beams used for matching and mapping, and which."""
        r = ranges
        laser = self.laser
        with np.errstate(invalid="ignore"):
            usable = (r >= laser.range_min) & (r <= self.max_range) & (r < self.max_urange)
        usable &= np.isfinite(r)
        rr = r[usable]
        pts = laser.origin + laser.directions[usable] * rr[:, None]
        return pts, usable

    def add_scan(self, stamp: float, ranges: Array, odom: Array) -> ScanPose | None:
        """One scan: its stamp (s), its ranges (as in the ``LaserScan``), and the base's
        pose in the odometry frame at that stamp.

        Input is data, not trusted geometry (each case counted in :attr:`tally`): a scan
        whose beam count is not the first scan's, or whose odometry pose is not finite or
        past :data:`~belvedere.bounded.POSE_METRES`, is skipped (None); NaN ranges are
        dropped; a scan that would grow a grid past :data:`GRID_CELLS` is matched but left
        out of the map (not a keyframe)."""
        ranges = np.asarray(ranges, dtype=np.float64)
        odom = np.asarray(odom, dtype=np.float64)
        if len(ranges) != len(self.laser.directions):
            self.tally.add(
                "skipped {count}: their beam count differs from the first scan's "
                f"{len(self.laser.directions):,}",
                first=f"{stamp:.3f} s: {len(ranges):,} beams",
            )
            return None
        problem = pose_problem(odom.tolist())
        if problem is not None:
            why, pose = problem
            self.tally.add(
                "skipped {count}: their odometry pose is " + why, first=f"{stamp:.3f} s: {pose}"
            )
            return None
        nan = int(np.count_nonzero(np.isnan(ranges)))
        if nan:
            self.tally.add("dropped {items} in {count}", items=nan, item="NaN range")
        pts, usable = self._points(ranges)
        skip = self.params.lskip + 1
        match_pts = pts if skip == 1 else pts[np.flatnonzero(usable)[: len(pts)] % skip == 0]
        if self._last_odom is None:
            self._start(odom)
            self._last_odom = odom
            self._remember(stamp)
            added = self._add_keyframe(stamp, ranges, pts)
            return ScanPose(pose=self.pose(), keyframe=added, score=1.0)
        motion = between(self._last_odom, odom)
        self._last_odom = odom
        dist = math.hypot(motion[0], motion[1])
        self._since_linear += dist
        self._travel += dist
        self._since_angular += abs(motion[2])
        predicted = compose(self._local, motion)
        if dist < 1e-4 and abs(motion[2]) < 1e-4:
            # Standing still: the odometry is right, and matching again changes nothing.
            self._local = predicted
            score = self._last_score
        else:
            score = self._match(predicted, motion, match_pts)
        self._last_score = score
        self._remember(stamp)
        p = self.params
        keyframe = (
            self._since_linear >= p.linearUpdate
            or self._since_angular >= p.angularUpdate
            or (p.temporalUpdate >= 0 and stamp - self._last_keyframe_stamp > p.temporalUpdate)
        )
        if keyframe:
            keyframe = self._add_keyframe(stamp, ranges, pts)
        return ScanPose(pose=self.pose(), keyframe=keyframe, score=score)

    def _start(self, odom: Array) -> None:
        # The map frame starts where the odometry frame is: the first pose is the odometry's.
        self._new_submap(odom, None)
        self._local = np.zeros(3)

    def _remember(self, stamp: float) -> None:
        s = self._state
        s.scans_stamp.append(float(stamp))
        s.scans_home.append(self._active[0])
        s.scans_local.append(self._local.copy())
        other, weight = self._blend()
        s.scans_other.append(other)
        s.scans_weight.append(weight)
        self._last_stamp = stamp

    def _blend(self) -> tuple[int, float]:
        """The newer active submap and how much of the pose to take from it: from none when
        it begins to all when the older one is finished, so that the trajectory does not
        jump where it passes from one submap to the next after the graph has moved them."""
        if len(self._active) < 2:
            return -1, 0.0
        half = max(self.tuning.submap_keyframes // 2, 1)
        done = self.submaps[self._active[0]].keyframes - half
        return self._active[1], min(
            max(done / max(self.tuning.submap_keyframes - half, 1), 0.0), 1.0
        )

    def _poses(self, home: Array, local: Array, other: Array, weight: Array) -> Array:
        """Map-frame poses from (home submap, pose in it, newer submap, its weight)."""
        graph = self.graph.poses
        poses = compose(graph[home], local)
        blended = other >= 0
        if blended.any():
            anchors = np.asarray(
                [self.submaps[int(o)].anchor[1] for o in other[blended]]  # type: ignore[index]
            )
            alt = compose(graph[other[blended]], between(anchors, local[blended]))
            base = poses[blended]
            d = alt - base
            d[:, 2] = (d[:, 2] + math.pi) % (2 * math.pi) - math.pi
            w = weight[blended][:, None]
            mixed = base + w * d
            mixed[:, 2] = (mixed[:, 2] + math.pi) % (2 * math.pi) - math.pi
            poses[blended] = mixed
        return poses

    def _match(self, predicted: Array, motion: Array, points: Array) -> float:
        sub = self.submaps[self._active[0]]
        grid = sub.grid
        if grid.points == 0 or len(points) < 3:
            self._local = predicted
            return 0.0
        inside = self._covered(sub, transform_points(predicted, points))
        if np.count_nonzero(inside) >= max(self.tuning.covered_min * len(points), 3):
            points = points[inside]
        p = self.params
        t = self.tuning
        dist = math.hypot(motion[0], motion[1])
        turn = abs(motion[2])
        sxy = max(t.prior_floor_xy, p.srr * dist + p.str * turn)
        sth = max(t.prior_floor_theta, p.stt * turn + p.srt * dist)
        info = np.array([1 / sxy**2, 1 / sxy**2, 1 / sth**2])
        iterations = max(p.iterations, 1) * 2
        result = refine(grid, points, predicted, predicted, info, iterations=iterations)
        if p.minimumScore > 0 and result.score * len(points) < p.minimumScore:
            result = self._recover(grid, points, predicted, info, iterations, result)
        self._local = result.pose
        # The least-squares covariance (the residuals' variance over the information of the
        # match and of the motion prior together) stands in for axes the lattice of
        # covariance() does not sample.
        dof = max(len(points) - 3, 1)
        self._last_match = _LastMatch(
            submap=self._active[0],
            version=grid.version,
            pose=result.pose,
            points=points,
            information=result.hessian + np.diag(info),
            variance=result.cost / dof,
        )
        return result.score

    def _covered(self, sub: _Submap, points: Array) -> npt.NDArray[np.bool_]:
        """Which points (submap frame) lie within the range the submap's keyframes mapped
        to: a wall seen on past that range ends there in the field, and the field's fading
        tail pulls the points beyond back along the wall — with a short ``maxUrange`` that
        pull, uneven between the two sides of a corridor, turned the match a little every
        time (0.5° a metre at 2 m)."""
        reach = min(self.max_urange, self.max_range)
        if not len(sub.sensors):
            return np.ones(len(points), dtype=bool)
        d = points[:, None, :] - sub.sensors[None, :, :]
        nearest = np.einsum("nkd,nkd->nk", d, d).min(axis=1)
        return np.asarray(nearest < reach * reach)

    def _recover(
        self,
        grid: FieldGrid,
        points: Array,
        predicted: Array,
        info: Array,
        iterations: int,
        first: Match,
    ) -> Match:
        """A match that scored under ``minimumScore``: search a lattice of ``lstep`` metres and
        ``astep`` radians, ``iterations`` steps each way around the prediction, refine the
        best; if that still scores under, keep the odometry's prediction (GMapping's "scan
        matching failed, using odometry")."""
        p = self.params
        pyramid = SearchPyramid(grid, self.tuning.search_depth)
        far = float(np.hypot(points[:, 0], points[:, 1]).max())
        step = max(self.resolution / max(far, self.resolution), 1e-4)
        found = pyramid.search(
            points,
            predicted,
            p.lstep * p.iterations,
            p.astep * p.iterations,
            min(step, p.astep),
            0.0,
        )
        if found is not None:
            again = refine(grid, points, found.pose, predicted, info, iterations=iterations)
            if again.score * len(points) >= p.minimumScore:
                return again
        logger.debug("scan matching failed, using odometry (score %.1f)", first.score * len(points))
        return Match(pose=predicted, score=first.score, hessian=first.hessian, cost=first.cost)

    # -------------------------------------------------------------- keyframes

    def _new_submap(self, pose: Array, anchor: tuple[int, Array] | None) -> int:
        index = len(self.submaps)
        self.submaps.append(
            _Submap(
                grid=FieldGrid(
                    self.resolution, *self._field, saturation=self.tuning.field_saturation
                ),
                anchor=anchor,
                free=FreeGrid(self.resolution * self.tuning.free_cells),
            )
        )
        self.graph.add_node(pose)
        if anchor is not None:
            parent, local = anchor
            d = math.hypot(local[0], local[1])
            t = self.tuning
            sxy = t.chain_sigma_xy[0] + t.chain_sigma_xy[1] * d
            sth = t.chain_sigma_theta[0] + t.chain_sigma_theta[1] * d
            self.graph.add_edge(parent, index, local, np.diag([1 / sxy**2, 1 / sxy**2, 1 / sth**2]))
        self._active.append(index)
        return index

    def _local_in(self, submap: int) -> Array:
        """The current pose in an active submap's frame."""
        tracking = self._active[0]
        if submap == tracking:
            return self._local
        anchor = self.submaps[submap].anchor
        assert anchor is not None
        assert anchor[0] == tracking
        return between(anchor[1], self._local)

    def _add_keyframe(self, stamp: float, ranges: Array, points: Array) -> bool:
        """Add the scan to the active submaps and the map; unless a grid would grow past
        :data:`GRID_CELLS` for it: then it is left out (counted) and nothing changes."""
        tracking = self._active[0]
        placed = []
        for s in self._active:
            at = self._local_in(s)
            placed.append((s, transform_points(at, points), *self._free_beams(at, ranges)))
        extent = self._extent(ranges)
        refusal = self._refusal(placed, compose(self.graph.poses[tracking], self._local), extent)
        if refusal is not None:
            self.tally.add(
                f"left {{count}} out of the map: a grid would grow past the cap of {GRID_CELLS:,} "
                "cells",
                first=f"{stamp:.3f} s: {refusal}",
            )
            return False
        self._since_linear = 0.0
        self._since_angular = 0.0
        self._last_keyframe_stamp = stamp
        t = self.tuning
        near = np.hypot(points[:, 0], points[:, 1]) <= t.loop_max_range
        search = points[near]
        if len(search) > t.loop_points:
            search = search[np.linspace(0, len(search) - 1, t.loop_points).astype(int)]
        kf = _Keyframe(
            stamp=float(stamp),
            ranges=ranges.astype(np.float32),
            home=tracking,
            local=self._local.copy(),
            search=search,
            extent=extent,
        )
        kf.other, kf.weight = self._blend()
        kf.travel = self._travel
        self.keyframes.append(kf)
        for s, world, sensor, ends in placed:
            sub = self.submaps[s]
            sub.grid.insert(world, undoable=self._keeps_before(s))
            sub.keyframes += 1
            self._add_free(sub, sensor, ends)
        g = compose(self.graph.poses[tracking], kf.local)
        self._grow_map_box(g, extent)
        self._kf_xy = np.vstack([self._kf_xy, g[None, :2]])
        self._kf_submaps.append(tracking)
        self._close_loops(len(self.keyframes) - 1, g)
        # Submap bookkeeping: the oldest is finished when full, a new one begins half-way.
        if self.submaps[tracking].keyframes >= t.submap_keyframes and len(self._active) > 1:
            self._finish(tracking)
        half = max(t.submap_keyframes // 2, 1)
        if len(self._active) == 1 and self.submaps[self._active[0]].keyframes >= half:
            tracking = self._active[0]
            pose = compose(self.graph.poses[tracking], self._local)
            fresh = self._new_submap(pose, (tracking, self._local.copy()))
            # (one scan around its own origin: within grid_reach, so it fits)
            self.submaps[fresh].grid.insert(points)
            self.submaps[fresh].keyframes += 1
            self._add_free(self.submaps[fresh], *self._free_beams(np.zeros(3), ranges))
        return True

    def _refusal(
        self, placed: list[tuple[int, Array, Array, Array]], pose: Array, extent: float
    ) -> str | None:
        """Why a keyframe at ``pose`` (the map's frame) cannot be added: the grid it would
        grow past :data:`GRID_CELLS` (a submap's, their free space's or the map's); None
        when all of them can hold it."""
        for s, world, sensor, ends in placed:
            sub = self.submaps[s]
            try:
                if len(world):
                    sub.grid.layout(world.min(axis=0), world.max(axis=0))
            except GridLimitError as err:
                return f"submap {s}'s grid to {err.cells:,.0f} cells"
            try:
                if len(ends) and sub.free is not None:
                    sub.free.layout(
                        np.minimum(ends.min(axis=0), sensor), np.maximum(ends.max(axis=0), sensor)
                    )
            except GridLimitError as err:
                return f"submap {s}'s free space to {err.cells:,.0f} cells"
        return self._map_refusal(pose, extent)

    def _keeps_before(self, submap: int) -> bool:
        """Whether an insert into ``submap`` must keep what it overwrites: the last match's
        covariance, not yet asked for, is computed against the grid as it was matched."""
        last = self._last_match
        if last is None or last.covariance is not None or last.submap != submap:
            return False
        if self.submaps[submap].grid.version != last.version:
            # A second insert since the match (a scan added without matching, standing
            # still): only one can be undone, so compute it now.
            last.covariance = self._sampled_covariance(last)
            return False
        return True

    def _free_beams(self, pose: Array, ranges: Array) -> tuple[Array, Array]:
        """The laser's position and the ends of the scan's beams (cut at ``maxUrange``) in
        a submap's frame, the scan taken at ``pose`` in it; a beam with no return (+inf,
        REP 117) passed all the way."""
        laser = self.laser
        with np.errstate(invalid="ignore"):
            ok = (ranges >= laser.range_min) & ~np.isnan(ranges)
        r = np.minimum(ranges[ok], self.max_urange)
        ends = laser.origin + laser.directions[ok] * r[:, None]
        sensor = transform_points(pose, laser.origin[None, :])[0]
        return sensor, transform_points(pose, ends)

    def _add_free(self, sub: _Submap, sensor: Array, ends: Array) -> None:
        """Count the beams from ``sensor`` to ``ends`` (:meth:`_free_beams`) as passing."""
        assert sub.free is not None
        sub.sensors = np.vstack([sub.sensors, sensor[None, :]])
        sub.free.add_beams(sensor, ends, self.tuning.free_short)

    def _finish(self, index: int) -> None:
        sub = self.submaps[index]
        sub.finished = True
        sub.grid.finish()
        sub.pyramid = SearchPyramid(sub.grid, self.tuning.search_depth)
        self._active.remove(index)
        successor = self._active[0]
        anchor = self.submaps[successor].anchor
        assert anchor is not None
        self._local = between(anchor[1], self._local)

    # ---------------------------------------------------------------- results

    def pose(self) -> Array:
        """The base's current pose in the map frame (zeros before the first scan)."""
        if not self._active:
            return np.zeros(3)
        home = self._active[0]
        pose = compose(self.graph.poses[home], self._local)
        other, weight = self._blend()
        if other < 0 or weight <= 0.0:
            return pose
        anchor = self.submaps[other].anchor
        assert anchor is not None
        alt = compose(self.graph.poses[other], between(anchor[1], self._local))
        d = alt - pose
        d[2] = (d[2] + math.pi) % (2 * math.pi) - math.pi
        mixed = pose + weight * d
        mixed[2] = (mixed[2] + math.pi) % (2 * math.pi) - math.pi
        return mixed

    def covariance(self) -> Array:
        """The covariance (x, y, yaw; the map's axes) of the last scan's pose, as GMapping
        estimates its proposal (:mod:`._proposal`): the poses of a lattice around the match
        (``llsamplerange``/``llsamplestep``, ``lasamplerange``/``lasamplestep``), weighted by
        the scan's likelihood there (``lsigma``, flattened by ``ogain``), evaluated against
        the submap the scan was matched to as it was then. Axes the lattice samples once
        take the match's least-squares covariance. Zero before any match.

        Computed when asked for (once per match)."""
        last = self._last_match
        if last is None:
            return np.zeros((3, 3))
        if last.covariance is None:
            last.covariance = self._sampled_covariance(last)
        yaw = float(self.graph.poses[last.submap][2])  # the submap's axes → the map's
        c, s = math.cos(yaw), math.sin(yaw)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        return np.asarray(rot @ last.covariance @ rot.T, dtype=np.float64)

    def _sampled_covariance(self, last: _LastMatch) -> Array:
        try:
            fallback: Array = np.asarray(
                np.linalg.inv(last.information) * max(last.variance, 1e-12), dtype=np.float64
            )
        except np.linalg.LinAlgError:
            fallback = np.zeros((3, 3))
        grid = self.submaps[last.submap].grid
        if grid.version == last.version:
            as_matched: contextlib.AbstractContextManager[None] = contextlib.nullcontext()
        elif grid.version == last.version + 1 and grid.undoable:
            as_matched = grid.before_last_insert()  # the scan itself was added since
        else:  # (_keeps_before computes it before that can happen)
            return fallback
        p = self.params
        with as_matched:
            return sampled_covariance(
                grid,
                last.points,
                last.pose,
                sigma=self._field[0],
                lsigma=p.lsigma,
                ogain=p.ogain,
                linear=(p.llsamplerange, p.llsamplestep),
                angular=(p.lasamplerange, p.lasamplestep),
                fallback=fallback,
            )

    def entropy(self) -> float:
        """The differential entropy (nats) of the pose estimate as a Gaussian of
        :meth:`covariance`: lower is surer. (slam_gmapping publishes the entropy of its
        particles' weights; one hypothesis has none, so that of its proposal takes its
        place.) 0 when the covariance is singular (before any match)."""
        det = float(np.linalg.det(self.covariance()))
        if det <= 0.0:
            return 0.0
        return 0.5 * math.log((2.0 * math.pi * math.e) ** 3 * det)

    def map_to_odom(self) -> Array:
        """The map → odom transform implied by the current pose and odometry."""
        if self._last_odom is None:
            return np.zeros(3)
        return compose(self.pose(), inverse(self._last_odom))

    def trajectory(self) -> tuple[Array, Array]:
        """Stamps (S,) and base poses (S, 3) in the map frame of every scan so far, at the
        graph's current estimate."""
        s = self._state
        if not s.scans_stamp:
            return np.zeros(0), np.zeros((0, 3))
        poses = self._poses(
            np.asarray(s.scans_home),
            np.asarray(s.scans_local),
            np.asarray(s.scans_other),
            np.asarray(s.scans_weight),
        )
        return np.asarray(s.scans_stamp), poses

    def keyframe_poses(self) -> Array:
        if not self.keyframes:
            return np.zeros((0, 3))
        kfs = self.keyframes
        return self._poses(
            np.asarray([kf.home for kf in kfs]),
            np.asarray([kf.local for kf in kfs]),
            np.asarray([kf.other for kf in kfs]),
            np.asarray([kf.weight for kf in kfs]),
        )
