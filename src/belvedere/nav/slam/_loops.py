"""The submap mapper's back end: keyframes searched for in finished submaps (loop closure),
closures weighed against each other and against the pose graph, the graph optimised.

:class:`LoopClosing` is mixed into :class:`~belvedere.nav.slam._slam.SubmapSlam`: it works on
the mapper's submaps, keyframes and graph, which the front end fills.
"""

from __future__ import annotations

import logging
import math

import numpy as np
import numpy.typing as npt

from belvedere.nav.slam._match import refine
from belvedere.nav.slam._posegraph import PoseGraph
from belvedere.nav.slam._se2 import between, compose, inverse, transform_points
from belvedere.nav.slam._types import Tuning, _Closure, _Keyframe, _Submap

__all__ = ["LoopClosing"]

logger = logging.getLogger("belvedere.nav.slam")

Array = npt.NDArray[np.float64]


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


def _degenerate(hessian: Array, ratio: float) -> bool:
    """Whether a match pins its translation down in one direction only."""
    block = hessian[:2, :2]
    eig = np.linalg.eigvalsh(block)
    return bool(eig[0] <= ratio * max(eig[1], 1e-12))


class LoopClosing:
    """Loop closure over the mapper's state (the attributes below, set by the mapper)."""

    tuning: Tuning
    resolution: float
    submaps: list[_Submap]
    keyframes: list[_Keyframe]
    graph: PoseGraph
    loop_closures: int
    refused_closures: int
    _active: list[int]
    _kf_xy: Array
    _kf_submaps: list[int]
    _pending: list[_Closure]
    _travel: float

    def _points(self, ranges: Array) -> tuple[Array, npt.NDArray[np.bool_]]:
        raise NotImplementedError  # the front end's

    def keyframe_poses(self) -> Array:
        raise NotImplementedError  # the mapper's

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
