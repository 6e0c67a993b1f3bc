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

Plain arrays in, plain arrays out; deterministic (no random numbers at all).
"""

from __future__ import annotations

import contextlib
import logging
import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from belvedere.maps import OccupancyMap
from belvedere.nav.slam._grid import FieldGrid, FreeGrid
from belvedere.nav.slam._match import Match, refine
from belvedere.nav.slam._occupancy import OccupancyCounts
from belvedere.nav.slam._params import GMappingParams
from belvedere.nav.slam._posegraph import PoseGraph
from belvedere.nav.slam._proposal import sampled_covariance
from belvedere.nav.slam._se2 import between, compose, inverse, transform_points
from belvedere.nav.slam._search import SearchPyramid

__all__ = ["LaserGeometry", "ScanPose", "SubmapSlam", "Tuning"]

logger = logging.getLogger("belvedere.nav.slam")

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class LaserGeometry:
    """Where the beams point, in the base frame (the laser assumed level)."""

    directions: Array
    """(B, 2) unit vectors, one per beam in the scan's order."""
    origin: Array
    """(2,) the laser's position on the base."""
    range_min: float
    range_max: float

    @classmethod
    def planar(
        cls,
        angle_min: float,
        angle_increment: float,
        count: int,
        range_min: float,
        range_max: float,
        laser_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
        upside_down: bool = False,
    ) -> LaserGeometry:
        """Beams of a ``LaserScan`` from a laser at ``laser_pose`` (x, y, yaw) on the base;
        ``upside_down`` mirrors them (a laser mounted with its z axis down)."""
        angles = angle_min + np.arange(count) * angle_increment
        if upside_down:
            angles = -angles
        yaw = laser_pose[2]
        directions = np.stack([np.cos(angles + yaw), np.sin(angles + yaw)], axis=1)
        return cls(
            directions=directions,
            origin=np.array(laser_pose[:2], dtype=np.float64),
            range_min=float(range_min),
            range_max=float(range_max),
        )


@dataclass(frozen=True)
class Tuning:
    """Constants of this mapper that GMapping has no parameter for."""

    submap_keyframes: int = 20
    field_sigma: float | None = None
    """Standard deviation (m) of the likelihood field; None: from ``sigma``."""
    field_radius: int | None = None
    """Kernel radius in cells; None: from ``kernelSize``."""
    field_saturation: float = 1.5
    """End points in a cell for its full weight. A wall seen once weighs 1/this: the part
    of a wall only the last keyframe saw is a lower ridge, whose slope drags the next scans
    back along the wall (towards the parts seen more often)."""
    prior_floor_xy: float = 0.02
    prior_floor_theta: float = 0.05
    """The odometry prior's least standard deviation per scan (m, rad): loose enough that
    a match seeing little (a short ``maxUrange``) is not pulled along with the odometry's
    heading creep."""
    loop_radius: float = 4.0
    """Finished submaps with a keyframe this near (m) are searched for loop closures."""
    loop_min_score: float = 0.45
    loop_window_xy: tuple[float, float, float] = (0.3, 0.08, 5.0)
    """Linear window: base (m), growth per metre travelled since the last closure, cap."""
    loop_window_theta: tuple[float, float, float] = (0.05, 0.0035, 0.35)
    loop_max_range: float = 20.0
    """Beams used to search for closures are cut to this range (m) (finer angular steps
    would otherwise be needed)."""
    loop_points: int = 90
    loop_sigma_xy: float = 0.05
    loop_sigma_theta: float = 0.01
    loop_huber: float = 3.0
    """Loop edges cost linearly beyond this Mahalanobis distance when the graph is
    optimised (a Huber kernel, as Cartographer's): a wrong closure that got this far pulls
    the graph with a bounded force, too weak to bend it, and is then dropped by
    ``loop_max_error``."""
    loop_min_travel: float = 15.0
    """Submaps nearer than this along the graph (m) are not searched for closures."""
    loop_min_ratio: float = 0.1
    """Closures whose translational information is this lopsided (corridors) are dropped."""
    loop_max_chi2: float = 100.0
    """Closures adding more than this to the graph's χ² (after optimising) are refused:
    their correction lies that far (squared, Mahalanobis) outside the drift the chain
    edges allow between their ends."""
    loop_max_error: float = 8.0
    """After optimising, a new closure this far (Mahalanobis) from the graph is dropped."""
    loop_max_contradiction: float = 0.2
    """A closure whose end points fall in the submap's free space more than this share of
    those the submap knows about is dropped."""
    free_cells: int = 4
    """The free-space grid's cells, in map cells."""
    covered_min: float = 0.5
    """The scan is matched with its points inside the submap's mapped range only, unless
    fewer than this share of them are."""
    free_short: float = 0.4
    """Beams count as passing up to this far (m) before their end."""
    loop_ambiguity: float = 0.9
    """A closure whose scan fits another pose in the window nearly as well (this fraction of
    the best score) is dropped. At 0.8, a short-range scan in a corridor (its two long walls
    most of its points) always had a second peak half a metre along and no closure was made;
    the contradiction check, the graph's error and its χ² gate stand behind this one."""
    agree_xy: float = 0.1
    agree_theta: float = 0.01
    """A closure moving its keyframe less than this agrees with the graph: accepted."""
    consistent_xy: float = 0.25
    consistent_theta: float = 0.025
    consistent_rate: float = 0.1
    """Two closures asking for corrections this close confirm each other (the linear part
    grows by this fraction of the correction asked for)."""
    pending_travel: float = 30.0
    """How long (metres travelled) a closure waits for confirmation."""
    loop_length: float = 1.0
    """A loop edge's length for the search windows (metres of travel it stands for)."""
    chain_sigma_xy: tuple[float, float] = (0.01, 0.01)
    """Submap chain edge: base (m), growth per metre."""
    chain_sigma_theta: tuple[float, float] = (0.002, 0.002)
    search_depth: int = 6
    optimize_error: float = 2.0
    """New loop edges this far (Mahalanobis) from the graph's estimate: optimise at once."""
    optimize_every: int = 10
    """Otherwise optimise after this many new loop edges."""
    optimize_iterations: int = 4


@dataclass(frozen=True)
class ScanPose:
    """The result of one scan: the base's pose in the map frame, whether the scan was added
    to the map (a keyframe), and the match's quality."""

    pose: Array
    keyframe: bool
    score: float


@dataclass
class _Submap:
    grid: FieldGrid
    anchor: tuple[int, Array] | None
    """(submap, pose in it) this one was created at."""
    keyframes: int = 0
    pyramid: SearchPyramid | None = None
    finished: bool = False
    free: FreeGrid | None = None
    """Where the submap's keyframes' beams passed (coarse)."""
    sensors: Array = field(default_factory=lambda: np.zeros((0, 2)))
    """Where the laser was (submap frame) for each keyframe inserted."""


@dataclass
class _Keyframe:
    stamp: float
    ranges: npt.NDArray[np.float32]
    home: int
    local: Array
    search: Array
    """The (subsampled, range-limited) points used to search for loop closures."""
    other: int = -1
    weight: float = 0.0
    travel: float = 0.0
    """Metres travelled (by odometry) when it was taken."""


@dataclass(eq=False)
class _Closure:
    keyframe: int
    submap: int
    measurement: Array
    """The keyframe's home submap seen from ``submap``."""
    information: Array
    """Of the keyframe's pose in ``submap`` (its own frame's axes)."""


def _moved_information(information: Array, local: Array) -> Array:
    """The information of ``z = m ∘ local⁻¹`` (the home submap seen from the old one) given
    that of ``m`` (the keyframe seen from the old one) in the keyframe's own axes: the same
    uncertainty, carried from the keyframe's origin to the home submap's."""
    # δz ≈ J δm with δm in the keyframe's axes; z's error is taken in z's axes.
    c, s = math.cos(local[2]), math.sin(local[2])
    lx, ly = local[0], local[1]
    inv_local = np.array([-(c * lx + s * ly), s * lx - c * ly])
    # Moving the keyframe by δm (its axes) moves z's origin by R(δθ)·inv_local + δt,
    # seen in z's axes: rotate the keyframe's axes into z's by -local's angle.
    rot = np.array([[c, s], [-s, c]])
    jac = np.eye(3)
    jac[:2, :2] = rot.T
    jac[:2, 2] = rot.T @ np.array([-inv_local[1], inv_local[0]])
    cov = jac @ np.linalg.inv(information) @ jac.T
    return np.asarray(np.linalg.inv(cov))


@dataclass
class _LastMatch:
    """What the pose's covariance is computed from when it is asked for (not before: a run
    that never asks pays nothing for it)."""

    submap: int
    version: int
    """The submap's grid's :attr:`~FieldGrid.version` the scan was matched against."""
    pose: Array
    """The match, in the submap's frame."""
    points: Array
    """The end points matched (the base's frame)."""
    information: Array
    variance: float
    """The match's least-squares information and its residuals' variance."""
    covariance: Array | None = None
    """Once computed (the submap's frame)."""


@dataclass
class _State:
    scans_stamp: list[float] = field(default_factory=list)
    scans_home: list[int] = field(default_factory=list)
    scans_local: list[Array] = field(default_factory=list)
    scans_other: list[int] = field(default_factory=list)
    scans_weight: list[float] = field(default_factory=list)


def _degenerate(hessian: Array, ratio: float) -> bool:
    """Whether a match pins its translation down in one direction only."""
    block = hessian[:2, :2]
    eig = np.linalg.eigvalsh(block)
    return bool(eig[0] <= ratio * max(eig[1], 1e-12))


class SubmapSlam:
    """Feed :meth:`add_scan` with each scan's ranges and the base's odometry pose; read
    :meth:`pose`, :meth:`trajectory`, :meth:`occupancy`."""

    def __init__(
        self,
        laser: LaserGeometry,
        params: GMappingParams | None = None,
        tuning: Tuning | None = None,
    ) -> None:
        self.params = params = params or GMappingParams()
        self.tuning = tuning = tuning or Tuning()
        self.laser = laser
        self.max_range = params.maxRange if params.maxRange is not None else laser.range_max - 0.01
        self.max_urange = params.maxUrange if params.maxUrange is not None else self.max_range
        self.resolution = params.delta
        sigma = tuning.field_sigma if tuning.field_sigma is not None else params.sigma
        radius = tuning.field_radius if tuning.field_radius is not None else params.kernelSize + 2
        self._field = (sigma, radius)
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

    def add_scan(self, stamp: float, ranges: Array, odom: Array) -> ScanPose:
        """One scan: its stamp (s), its ranges (as in the ``LaserScan``), and the base's
        pose in the odometry frame at that stamp."""
        ranges = np.asarray(ranges, dtype=np.float64)
        odom = np.asarray(odom, dtype=np.float64)
        if len(ranges) != len(self.laser.directions):
            message = f"a scan of {len(ranges)} beams, expected {len(self.laser.directions)}"
            raise ValueError(message)
        pts, usable = self._points(ranges)
        skip = self.params.lskip + 1
        match_pts = pts if skip == 1 else pts[np.flatnonzero(usable)[: len(pts)] % skip == 0]
        if self._last_odom is None:
            self._start(odom)
            self._last_odom = odom
            self._remember(stamp)
            self._add_keyframe(stamp, ranges, pts)
            return ScanPose(pose=self.pose(), keyframe=True, score=1.0)
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
            self._add_keyframe(stamp, ranges, pts)
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

    def _add_keyframe(self, stamp: float, ranges: Array, points: Array) -> None:
        self._since_linear = 0.0
        self._since_angular = 0.0
        self._last_keyframe_stamp = stamp
        tracking = self._active[0]
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
        )
        kf.other, kf.weight = self._blend()
        kf.travel = self._travel
        self.keyframes.append(kf)
        for s in self._active:
            sub = self.submaps[s]
            at = self._local_in(s)
            sub.grid.insert(transform_points(at, points), undoable=self._keeps_before(s))
            sub.keyframes += 1
            self._add_free(sub, at, ranges)
        g = compose(self.graph.poses[tracking], kf.local)
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
            self.submaps[fresh].grid.insert(points)
            self.submaps[fresh].keyframes += 1
            self._add_free(self.submaps[fresh], np.zeros(3), ranges)

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

    def _add_free(self, sub: _Submap, pose: Array, ranges: Array) -> None:
        """Count the scan's beams (up to ``maxUrange``) as passing, in the submap's frame; a
        beam with no return (+inf, REP 117) passed all the way."""
        assert sub.free is not None
        laser = self.laser
        with np.errstate(invalid="ignore"):
            ok = (ranges >= laser.range_min) & ~np.isnan(ranges)
        r = np.minimum(ranges[ok], self.max_urange)
        ends = laser.origin + laser.directions[ok] * r[:, None]
        sensor = transform_points(pose, laser.origin[None, :])[0]
        sub.sensors = np.vstack([sub.sensors, sensor[None, :]])
        sub.free.add_beams(sensor, transform_points(pose, ends), self.tuning.free_short)

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

    # ----------------------------------------------------------- loop closure

    def _close_loops(self, k: int, g: Array) -> None:
        t = self.tuning
        kf = self.keyframes[k]
        tracking = kf.home
        if len(kf.search) < 10:
            return
        recent = min(self._active) - 1
        if recent <= 0:
            return
        # How far the graph puts each old submap from here, in metres of travel: the search
        # window grows with it (drift), and shrinks once a loop has been closed nearby.
        travel = self.graph.distances(tracking)[:recent] + math.hypot(kf.local[0], kf.local[1])
        wxy = np.minimum(t.loop_window_xy[0] + t.loop_window_xy[1] * travel, t.loop_window_xy[2])
        wth = np.minimum(
            t.loop_window_theta[0] + t.loop_window_theta[1] * travel, t.loop_window_theta[2]
        )
        kf_sub = np.asarray(self._kf_submaps)
        # Only submaps far along the graph: nearer ones are held by the chain already, and
        # matching against them mostly finds the chain's own errors in corridors.
        old = (kf_sub < recent) & (travel[np.minimum(kf_sub, recent - 1)] >= t.loop_min_travel)
        d = np.hypot(self._kf_xy[old, 0] - g[0], self._kf_xy[old, 1] - g[1])
        near = d < t.loop_radius + wxy[kf_sub[old]]
        candidates = np.unique(kf_sub[old][near])
        if not len(candidates):
            return
        far = float(np.hypot(kf.search[:, 0], kf.search[:, 1]).max())
        step = self.resolution / max(far, self.resolution)
        found_edges: list[tuple[int, Array, Array]] = []
        pts: Array | None = None
        for b in candidates:
            sub = self.submaps[int(b)]
            if sub.pyramid is None:
                continue
            center = between(self.graph.poses[b], g)
            found = sub.pyramid.search(
                kf.search,
                center,
                float(wxy[b]),
                float(wth[b]),
                step,
                t.loop_min_score,
                ambiguity=t.loop_ambiguity,
            )
            if found is None or found.runner_up > 0.0:
                continue
            if pts is None:
                pts, _ = self._points(kf.ranges.astype(np.float64))
            match = refine(sub.grid, pts, found.pose, iterations=10)
            if match.score < t.loop_min_score or _degenerate(match.hessian, t.loop_min_ratio):
                continue
            if self._contradiction(sub, pts, match.pose) > t.loop_max_contradiction:
                continue
            # The match's covariance (residual variance over its information), with a floor:
            # a closure along a corridor pins the corridor's direction down loosely only.
            dof = max(len(pts) - 3, 1)
            try:
                cov = np.linalg.inv(match.hessian) * (match.cost / dof)
            except np.linalg.LinAlgError:
                continue
            cov = cov + np.diag([t.loop_sigma_xy**2, t.loop_sigma_xy**2, t.loop_sigma_theta**2])
            found_edges.append((int(b), compose(match.pose, inverse(kf.local)), np.linalg.inv(cov)))
        self._consider(k, found_edges)

    def _contradiction(self, sub: _Submap, points: Array, pose: Array) -> float:
        """Of the scan's end points at ``pose`` that the submap has an opinion on, the share
        it saw as free space (its beams passed there, no wall near): a scan fitted to the
        wrong bay of a corridor puts its far walls in the submap's open corridor."""
        assert sub.free is not None
        world = transform_points(pose, points)
        crossed = sub.free.at(world) >= 2
        value, _ = sub.grid.sample(world)
        supported = value >= 0.3
        against = crossed & (value < 0.1)
        known = int(against.sum() + supported.sum())
        return float(against.sum() / known) if known >= 10 else 0.0

    def _correction(self, closure: _Closure) -> tuple[Array, Array]:
        """Where the closure would put its keyframe, and where the graph has it now."""
        kf = self.keyframes[closure.keyframe]
        now = compose(self.graph.poses[kf.home], kf.local)
        there = compose(self.graph.poses[closure.submap], compose(closure.measurement, kf.local))
        return there, now

    def _agree(self, a: _Closure, b: _Closure) -> bool:
        """Whether moving ``a``'s keyframe where ``a`` says, and everything near it along,
        puts ``b``'s keyframe where ``b`` says."""
        t = self.tuning
        there_a, now_a = self._correction(a)
        there_b, now_b = self._correction(b)
        moved = compose(compose(there_a, inverse(now_a)), now_b)
        d = between(moved, there_b)
        size = math.hypot(*between(now_b, there_b)[:2])
        return bool(
            math.hypot(d[0], d[1]) <= t.consistent_xy + t.consistent_rate * size
            and abs(d[2]) <= t.consistent_theta
        )

    def _consider(self, k: int, found: list[tuple[int, Array, Array]]) -> None:
        """Accept closures that agree with the graph as it is; hold the others until a
        closure from another keyframe asks for the same correction (two different views
        of a corridor seldom alias the same way)."""
        t = self.tuning
        accepted: list[_Closure] = []
        for b, z, info in found:
            closure = _Closure(keyframe=k, submap=b, measurement=z, information=info)
            c = between(*reversed(self._correction(closure)))
            logger.debug(
                "closure t=%.1f keyframe %d (submap %d) -> %d: correction %+.2f %+.2f %+.1f°",
                self.keyframes[k].stamp,
                k,
                self.keyframes[k].home,
                b,
                c[0],
                c[1],
                math.degrees(c[2]),
            )
            if math.hypot(c[0], c[1]) <= t.agree_xy and abs(c[2]) <= t.agree_theta:
                accepted.append(closure)
                continue
            partners = [p for p in self._pending if p.keyframe != k and self._agree(closure, p)]
            if partners:
                accepted.append(closure)
                accepted.extend(partners)
                self._pending = [p for p in self._pending if p not in partners]
            else:
                self._pending.append(closure)
        self._pending = [
            p
            for p in self._pending
            if self._travel - self.keyframes[p.keyframe].travel < t.pending_travel
        ]
        if not accepted:
            return
        added: list[int] = []
        chi2_before = self.graph.cost()
        poses_before = self.graph.poses.copy()
        for closure in accepted:
            added.append(self.graph.edge_count)
            home = self.keyframes[closure.keyframe].home
            # The measurement is the keyframe's pose in the old submap, turned into the home
            # submap's: its covariance turns with it (the home frame's origin is elsewhere).
            self.graph.add_edge(
                closure.submap,
                home,
                closure.measurement,
                _moved_information(closure.information, self.keyframes[closure.keyframe].local),
                huber=t.loop_huber,
                length=t.loop_length,
            )
        logger.debug(
            "accepted: %s",
            ", ".join(f"{self.keyframes[c.keyframe].stamp:.1f}->{c.submap}" for c in accepted),
        )
        self._optimize()
        # A closure the rest of the graph cannot agree with is most likely a false match.
        while added:
            errors = self.graph.errors()[added]
            worst = int(np.argmax(errors))
            if errors[worst] <= t.loop_max_error:
                break
            removed = added.pop(worst)
            logger.debug("closure edge %d dropped: %.1f from the graph", removed, errors[worst])
            self.refused_closures += 1
            self.graph.remove_edge(removed)
            added = [e - 1 if e > removed else e for e in added]
            self._optimize()
        # The Mahalanobis gate: the χ² the closures add to the graph, once it has bent to
        # them as far as its chain edges (the front end's drift model) allow, is their
        # correction's squared distance in the uncertainty grown along the path between
        # their ends. Closures that need the trajectory bent far beyond that are refused.
        grown = self.graph.cost() - chi2_before
        if added and grown > t.loop_max_chi2:
            logger.debug("closures refused: they add %.1f to the graph's chi2", grown)
            for e in sorted(added, reverse=True):
                self.graph.remove_edge(e)
            self.graph.poses = poses_before
            self._refresh_keyframe_xy()
            self.refused_closures += len(added)
            return
        self.loop_closures += len(added)
        self._settle_pending()

    def _settle_pending(self) -> None:
        """With a loop confirmed, the closures still waiting for a partner are tried one by
        one on the bent graph: each that the graph takes within the same gates stays. One
        seen on the way into the loop (its partner expired before the loop was confirmed)
        would otherwise leave the stretch before the confirmed closure bent by the whole
        correction spread along the loop, rather than held where it was seen."""
        t = self.tuning
        for closure in list(self._pending):
            cost_before = self.graph.cost()
            poses_before = self.graph.poses.copy()
            edge = self.graph.edge_count
            self.graph.add_edge(
                closure.submap,
                self.keyframes[closure.keyframe].home,
                closure.measurement,
                _moved_information(closure.information, self.keyframes[closure.keyframe].local),
                huber=t.loop_huber,
                length=t.loop_length,
            )
            self._optimize()
            error = float(self.graph.errors()[edge])
            grown = self.graph.cost() - cost_before
            if error > t.loop_max_error or grown > t.loop_max_chi2:
                logger.debug("pending closure refused: error %.1f, chi2 +%.1f", error, grown)
                self.graph.remove_edge(edge)
                self.graph.poses = poses_before
                self._refresh_keyframe_xy()
                continue
            logger.debug(
                "pending closure %.1f->%d settled: error %.1f, chi2 +%.1f",
                self.keyframes[closure.keyframe].stamp,
                closure.submap,
                error,
                grown,
            )
            self._pending.remove(closure)
            self.loop_closures += 1

    def _optimize(self) -> None:
        self.graph.optimize(iterations=self.tuning.optimize_iterations)
        self._refresh_keyframe_xy()

    def _refresh_keyframe_xy(self) -> None:
        self._kf_xy = self.keyframe_poses()[:, :2]

    # ---------------------------------------------------------------- results

    def pose(self) -> Array:
        """The base's current pose in the map frame."""
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

    def occupancy(self) -> OccupancyMap:
        """The occupancy grid traced from every keyframe at its current pose (keyframes
        already traced at the same pose are not traced again)."""
        p = self.params
        poses = self.keyframe_poses()
        done = len(self._map_poses)
        if (
            self._map is None
            or done > len(poses)
            or (done and np.abs(poses[:done] - self._map_poses).max() > 1e-9)
        ):
            self._map = OccupancyCounts(self.resolution, p.xmin, p.ymin, p.xmax, p.ymax)
            done = 0
        if done < len(poses):
            self._trace(self._map, poses[done:], self.keyframes[done:])
        self._map_poses = poses
        return self._map.to_map(p.occ_thresh)

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
