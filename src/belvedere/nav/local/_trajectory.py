"""``base_local_planner/TrajectoryPlannerROS``: Trajectory Rollout (and its DWA mode).

Each cycle samples forward velocities with rotations (and, for a holonomic robot, two slight
strafes), then rotations in place; simulates every sample for ``sim_time`` under the
acceleration limits; drops those whose footprint meets an obstacle or leaves the grid or whose
points have no free path to the plan or to the local goal; and drives the cheapest:
``pdist·path_dist + gdist·goal_dist + occdist·max_cell_cost`` at the trajectory's end. In-place
rotations are chosen by how close to the goal a point ``heading_lookahead`` ahead would be.
With nothing valid a holonomic robot tries pure strafes, and then the robot backs up at
``escape_vel`` (escaping until it moved ``escape_reset_dist`` or turned
``escape_reset_theta``). Within ``xy_goal_tolerance`` of the goal it stops under its
acceleration limits and turns in place to the goal's yaw.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.nav.costmap import INSCRIBED, CostGrid
from belvedere.nav.local._base import (
    Command,
    NoTrajectoryError,
    angle_diff,
    as_path,
    sign,
    slowed,
    stopped,
)
from belvedere.nav.local._maps import (
    DistanceMap,
    FootprintModel,
    clipped_cells,
    filled_footprint_cells,
    follow_plan,
    footprint_model,
    grid_cells,
    plan_cells,
    used_points_cost,
    wavefront,
    wavefronts,
)
from belvedere.nav.local._params import TrajectoryPlannerParams
from belvedere.nav.local._rollout import Rollouts, rollout

__all__ = ["TrajectoryPlannerROS"]

Floats = npt.NDArray[np.float64]
Pose = tuple[float, float, float]

_STOPPED = 1e-2
"""TrajectoryPlannerROS's thresholds below which the robot counts as stopped."""


@dataclass
class _Cycle:
    """What one cycle's scoring reads: the grid, the footprint and the distance maps."""

    grid: CostGrid
    model: FootprintModel
    path_map: DistanceMap
    goal_map: DistanceMap
    plan: Floats
    """The plan's stretch in the local grid."""


class TrajectoryPlannerROS:
    """base_local_planner's TrajectoryPlannerROS over plain arrays (see the module doc)."""

    name = "base_local_planner/TrajectoryPlannerROS"

    def __init__(self, params: TrajectoryPlannerParams | Mapping[str, Any] | None = None) -> None:
        if params is None or not isinstance(params, TrajectoryPlannerParams):
            params = TrajectoryPlannerParams.from_mapping(params or {})
        self._params = params
        self._plan: Floats = np.zeros((0, 3))
        self._latched = False
        self._rotating_to_goal = False
        self._reached_goal = False
        self._model: FootprintModel | None = None
        # oscillation and escape state (TrajectoryPlanner's flags)
        self._prev = (0.0, 0.0)
        self._escape = (0.0, 0.0, 0.0)
        self._escaping = False
        self._rotating_left = self._rotating_right = False
        self._strafe_left = self._strafe_right = False
        self._stuck_left = self._stuck_right = False
        self._stuck_left_strafe = self._stuck_right_strafe = False

    @property
    def params(self) -> TrajectoryPlannerParams:
        return self._params

    def set_plan(self, path: Floats) -> None:
        self._plan = as_path(path)
        self._latched = False
        self._reached_goal = False

    def goal_reached(self, pose: Pose | Floats, velocity: Pose | Floats) -> bool:
        # TrajectoryPlannerROS answers from its last cycle: it reached the goal when that
        # cycle found the robot within both tolerances and commanded zero
        return self._reached_goal

    # -- one cycle --------------------------------------------------------------------------

    def compute(
        self, grid: CostGrid, pose: Pose | Floats, velocity: Pose | Floats, footprint: Floats
    ) -> Command:
        p = self._params
        x, y, yaw = (float(v) for v in pose)
        vel = (float(velocity[0]), float(velocity[1]), float(velocity[2]))
        local, self._plan = follow_plan(
            self._plan, grid, x, y, prune=p.prune_plan, planner="TrajectoryPlannerROS"
        )
        cycle = self._prepare(grid, (x, y, yaw), footprint, local)
        goal_x, goal_y, goal_yaw = (float(v) for v in local[-1])
        if self._latched or math.hypot(goal_x - x, goal_y - y) <= p.xy_goal_tolerance:
            if p.latch_xy_goal_tolerance:
                self._latched = True
            return self._at_goal(cycle, (x, y, yaw), vel, goal_yaw)
        best = self._create_trajectories(cycle, (x, y, yaw), vel)
        if best is None:
            message = (
                "TrajectoryPlannerROS: no valid trajectory (every sample collides, leaves the "
                "local costmap or loses the path to the goal)"
            )
            raise NoTrajectoryError(message)
        rollouts, s = best
        vx, vy, vth = (float(v) for v in rollouts.samples[s])
        return Command(vx, vy, vth, rollouts.points(s))

    def _prepare(self, grid: CostGrid, pose: Pose, footprint: Floats, local: Floats) -> _Cycle:
        model = self._model = footprint_model(self._model, footprint, grid.resolution)
        # the cells under the robot do not stop the path's wave (MapGrid's within_robot)
        under = filled_footprint_cells(grid, *pose, model.footprint)
        columns, rows = plan_cells(grid, local[:, :2])
        goal_cell = (columns[-1:], rows[-1:])
        if np.any(under & (grid.costs >= INSCRIBED)):
            path_map = wavefront(grid, (columns, rows), passable=under)
            goal_map = wavefront(grid, goal_cell)
        else:
            # nothing under the robot blocks the wave: both maps share one graph
            path_map, goal_map = wavefronts(grid, [(columns, rows), goal_cell])
        return _Cycle(grid, model, path_map, goal_map, local)

    # -- scoring ----------------------------------------------------------------------------

    def _steps(self, samples: Floats) -> npt.NDArray[np.intp]:
        p = self._params
        if p.heading_scoring:
            fixed = int(p.sim_time / p.sim_granularity + 0.5)
            return np.full(len(samples), max(fixed, 1), dtype=np.intp)
        vmag = np.hypot(samples[:, 0], samples[:, 1])
        # ROS divides the rotation rate (not the angle turned in sim_time) by the angular
        # granularity here
        n = (
            np.maximum(
                vmag * p.sim_time / p.sim_granularity,
                np.abs(samples[:, 2]) / p.angular_sim_granularity,
            )
            + 0.5
        ).astype(np.intp)
        steps: npt.NDArray[np.intp] = np.maximum(n, 1)
        return steps

    def _simulate(self, pose: Pose, vel: Pose, samples: Floats) -> Rollouts:
        p = self._params
        return rollout(
            pose,
            vel,
            samples,
            self._steps(samples),
            p.sim_time,
            (p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta),
            accelerate=True,
            first_increment=1,
        )

    def _score(self, cycle: _Cycle, r: Rollouts) -> tuple[Floats, npt.NDArray[np.float64]]:
        """(cost, code) per sample: the cost where ``code`` is 0, else -1 (footprint collides
        or leaves the grid) or -2 (a point without a free path to the plan or local goal),
        whichever its earliest bad point shows."""
        p = self._params
        grid = cycle.grid
        ic, jc, inside = clipped_cells(grid, r.x, r.y)
        centre = grid.costs[jc, ic].astype(np.float64)
        count = len(r.samples)
        if p.simple_attractor:
            gx, gy = cycle.plan[-1, 0], cycle.plan[-1, 1]
            goal_dist = (r.x - gx) ** 2 + (r.y - gy) ** 2
            path_dist = np.zeros_like(goal_dist)
            update = r.used.copy()
            lost = np.zeros_like(inside)
        else:
            path_dist = cycle.path_map.dist[jc, ic]
            goal_dist = cycle.goal_map.dist[jc, ic]
            if p.heading_scoring:
                t = np.arange(r.x.shape[1])[None, :] * r.dt[:, None]
                update = (
                    (t >= p.heading_scoring_timestep)
                    & (t < p.heading_scoring_timestep + r.dt[:, None])
                    & r.used
                )
            else:
                update = r.used.copy()
            impossible = cycle.path_map.obstacle_cost
            lost = update & ((path_dist >= impossible) | (goal_dist >= impossible))
        # the footprint matters up to a trajectory's first lost or off-grid point: a collision
        # there or before decides its failure, and a trajectory with one fails anyway
        k = np.arange(r.x.shape[1])[None, :]
        ends = (lost | ~inside) & r.used
        first_end = np.where(ends.any(axis=1), np.argmax(ends, axis=1), r.x.shape[1])
        alive = r.used & (k <= first_end[:, None])
        fp_cost, fp_valid = used_points_cost(cycle.model, grid, r.x, r.y, r.yaw, alive)
        collide = ~inside | ~fp_valid
        bad_point = (collide | lost) & r.used
        has_bad = bad_point.any(axis=1)
        first_bad = np.where(has_bad, np.argmax(bad_point, axis=1), r.x.shape[1])
        rows = np.arange(count)
        code = np.zeros(count)
        at_bad = np.minimum(first_bad, r.x.shape[1] - 1)
        code[has_bad] = np.where(collide[rows, at_bad], -1.0, -2.0)[has_bad]
        occ = np.where(r.used, np.maximum(fp_cost, centre), 0.0).max(axis=1)
        # the path and goal distances of the last scored point
        last = np.where(update, k, -1).max(axis=1)
        scored = last >= 0
        lk = np.maximum(last, 0)
        pd = np.where(scored, path_dist[rows, lk], 0.0)
        gd = np.where(scored, goal_dist[rows, lk], 0.0)
        pdist, gdist, occdist = p.path_distance_bias, p.goal_distance_bias, p.occdist_scale
        if p.meter_scoring:
            pdist, gdist, occdist = (
                pdist * grid.resolution,
                gdist * grid.resolution,
                occdist * grid.resolution,
            )
        cost = pdist * pd + gdist * gd + occdist * occ
        if p.heading_scoring:
            heading = np.zeros(count)
            for s in np.flatnonzero(~has_bad & scored):
                heading[s] = self._heading_diff(
                    cycle, r.x[s, lk[s]], r.y[s, lk[s]], r.yaw[s, lk[s]]
                )
            cost = cost + 0.3 * heading
        return cost, code

    def _heading_diff(self, cycle: _Cycle, x: float, y: float, heading: float) -> float:
        """How far ``heading`` is from the bearing to the farthest plan pose in clear line of
        sight (headingDiff)."""
        grid = cycle.grid
        here = grid.world_to_map(x, y)
        if here is None:
            return math.inf
        pi, pj, inside = grid_cells(grid, cycle.plan[:, 0], cycle.plan[:, 1])
        pi, pj = pi[inside], pj[inside]
        if len(pi) == 0:
            return math.inf
        # the lines from here to the plan poses, sampled a cell apart along their longer
        # axis: the farthest pose's first (usually in sight), then all of them
        for columns, rows in ((pi[-1:], pj[-1:]), (pi, pj)):
            sight = self._farthest_in_sight(grid, here, columns, rows)
            if sight is not None:
                gx, gy = grid.map_to_world(*sight)
                return abs(angle_diff(heading, math.atan2(gy - y, gx - x)))
        return math.inf

    @staticmethod
    def _farthest_in_sight(
        grid: CostGrid, here: tuple[int, int], pi: npt.NDArray[np.intp], pj: npt.NDArray[np.intp]
    ) -> tuple[int, int] | None:
        steps = np.maximum(np.abs(pi - here[0]), np.abs(pj - here[1]))
        t = np.arange(int(steps.max()) + 1)[None, :] / np.maximum(steps, 1)[:, None]
        t = np.minimum(t, 1.0)
        ci = np.rint(here[0] + (pi - here[0])[:, None] * t).astype(np.intp)
        cj = np.rint(here[1] + (pj - here[1])[:, None] * t).astype(np.intp)
        clear = np.flatnonzero((grid.costs[cj, ci] < INSCRIBED).all(axis=1))
        if len(clear) == 0:
            return None
        return int(pi[clear[-1]]), int(pj[clear[-1]])

    # -- sampling (createTrajectories) ------------------------------------------------------

    def _create_trajectories(
        self, cycle: _Cycle, pose: Pose, vel: Pose
    ) -> tuple[Rollouts, int] | None:
        p = self._params
        x, y, yaw = pose
        vx, _, vth = vel
        max_x, min_x = p.max_vel_x, p.min_vel_x
        max_th, min_th = p.max_vel_theta, p.min_vel_theta
        end_x, end_y = cycle.plan[-1, 0], cycle.plan[-1, 1]
        max_x = min(max_x, math.hypot(end_x - x, end_y - y) / p.sim_time)
        reach = p.sim_period if p.dwa else p.sim_time
        max_x = max(min(max_x, vx + p.acc_lim_x * reach), p.min_vel_x)
        min_x = max(p.min_vel_x, vx - p.acc_lim_x * reach)
        max_th = min(max_th, vth + p.acc_lim_theta * reach)
        min_th = max(min_th, vth - p.acc_lim_theta * reach)
        dvx = (max_x - min_x) / (p.vx_samples - 1) if p.vx_samples > 1 else math.inf
        dvth = (max_th - min_th) / (p.vtheta_samples - 1) if p.vtheta_samples > 1 else math.inf

        forward: list[tuple[float, float, float]] = []
        if not self._escaping:
            for a in range(p.vx_samples):
                vx_samp = min_x + a * dvx if p.vx_samples > 1 else min_x
                forward.append((vx_samp, 0.0, 0.0))
                forward.extend(
                    (vx_samp, 0.0, min_th + b * dvth) for b in range(p.vtheta_samples - 1)
                )
            if p.holonomic_robot:
                forward += [(0.1, 0.1, 0.0), (0.1, -0.1, 0.0)]
        raw_turns = [
            min_th + b * dvth if p.vtheta_samples > 1 else min_th for b in range(p.vtheta_samples)
        ]
        turns = [
            (
                0.0,
                0.0,
                max(v, p.min_in_place_vel_theta) if v > 0 else min(v, -p.min_in_place_vel_theta),
            )
            for v in raw_turns
        ]
        batch = np.array(forward + turns, dtype=np.float64).reshape(-1, 3)
        r = self._simulate(pose, vel, batch)
        cost, code = self._score(cycle, r)
        best = -1
        for s in range(len(forward)):
            if code[s] == 0 and (best < 0 or cost[s] < cost[best]):
                best = s
        heading_dist = math.inf
        for b, raw in enumerate(raw_turns):
            s = len(forward) + b
            if code[s] != 0 or not (raw > dvth or raw < -dvth):
                continue
            if not (best < 0 or cost[s] <= cost[best] or r.samples[best, 1] != 0.0):
                continue
            ahead = self._ahead_goal_dist(cycle, r, s)
            if ahead is None or ahead >= heading_dist:
                continue
            if (raw < 0 and not self._stuck_left) or (raw > 0 and not self._stuck_right):
                best, heading_dist = s, ahead
        if best >= 0:
            self._after_choice(r.samples[best], pose)
            return r, best

        if p.holonomic_robot and p.y_vels:
            strafes = np.array([(0.0, v, 0.0) for v in p.y_vels])
            r = self._simulate(pose, vel, strafes)
            cost, code = self._score(cycle, r)
            best = -1
            for s, vy in enumerate(p.y_vels):
                if code[s] != 0 or not (best < 0 or cost[s] <= cost[best]):
                    continue
                ahead = self._ahead_goal_dist(cycle, r, s)
                if ahead is None or ahead >= heading_dist:
                    continue
                if (vy > 0 and not self._stuck_left_strafe) or (
                    vy < 0 and not self._stuck_right_strafe
                ):
                    best, heading_dist = s, ahead
            if best >= 0:
                self._after_choice(r.samples[best], pose)
                return r, best

        # nothing valid: back up slowly, even into a collision, unless the path is lost
        r = self._simulate(pose, vel, np.array([[p.escape_vel, 0.0, 0.0]]))
        cost, code = self._score(cycle, r)
        if math.hypot(x - self._prev[0], y - self._prev[1]) > p.oscillation_reset_dist:
            self._reset_oscillation()
        if not self._escaping and code[0] > -2.0:
            self._escape = (x, y, yaw)
            self._escaping = True
        self._check_escape(pose)
        if code[0] == -2.0:
            return None
        return r, 0

    def _ahead_goal_dist(self, cycle: _Cycle, r: Rollouts, s: int) -> float | None:
        n = int(r.steps[s]) - 1
        ex, ey, eth = r.x[s, n], r.y[s, n], r.yaw[s, n]
        cell = cycle.grid.world_to_map(
            ex + self._params.heading_lookahead * math.cos(eth),
            ey + self._params.heading_lookahead * math.sin(eth),
        )
        if cell is None:
            return None
        return float(cycle.goal_map.dist[cell[1], cell[0]])

    def _after_choice(self, sample: Floats, pose: Pose) -> None:
        """TrajectoryPlanner's bookkeeping against oscillating in place."""
        x, y, _ = pose
        vx, vy, vth = (float(v) for v in sample)
        if not vx > 0:
            if vth < 0:
                if self._rotating_right:
                    self._stuck_right = True
                self._rotating_right = True
            elif vth > 0:
                if self._rotating_left:
                    self._stuck_left = True
                self._rotating_left = True
            elif vy > 0:
                if self._strafe_right:
                    self._stuck_right_strafe = True
                self._strafe_right = True
            elif vy < 0:
                if self._strafe_left:
                    self._stuck_left_strafe = True
                self._strafe_left = True
            self._prev = (x, y)
        if math.hypot(x - self._prev[0], y - self._prev[1]) > self._params.oscillation_reset_dist:
            self._reset_oscillation()
        self._check_escape(pose)

    def _reset_oscillation(self) -> None:
        self._rotating_left = self._rotating_right = False
        self._strafe_left = self._strafe_right = False
        self._stuck_left = self._stuck_right = False
        self._stuck_left_strafe = self._stuck_right_strafe = False

    def _check_escape(self, pose: Pose) -> None:
        x, y, yaw = pose
        ex, ey, eth = self._escape
        if (
            math.hypot(x - ex, y - ey) > self._params.escape_reset_dist
            or abs(angle_diff(eth, yaw)) > self._params.escape_reset_theta
        ):
            self._escaping = False

    # -- at the goal ------------------------------------------------------------------------

    def _valid(self, cycle: _Cycle, pose: Pose, vel: Pose, sample: Pose) -> bool:
        """checkTrajectory: whether this command's rollout is valid."""
        r = self._simulate(pose, vel, np.array([sample]))
        _, code = self._score(cycle, r)
        return bool(code[0] == 0)

    def _at_goal(self, cycle: _Cycle, pose: Pose, vel: Pose, goal_yaw: float) -> Command:
        p = self._params
        if abs(angle_diff(pose[2], goal_yaw)) <= p.yaw_goal_tolerance:
            self._rotating_to_goal = False
            self._latched = False
            self._reached_goal = True
            return Command(0.0, 0.0, 0.0)
        if not self._rotating_to_goal and not stopped(vel, _STOPPED, _STOPPED):
            period = p.sim_period
            cmd = slowed(vel, (p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta), period)
            if not self._valid(cycle, pose, vel, cmd):
                message = "TrajectoryPlannerROS: cannot slow down at the goal without a collision"
                raise NoTrajectoryError(message)
            return Command(*cmd)
        self._rotating_to_goal = True
        vth = self._rotate_to_goal(pose, vel, goal_yaw)
        if not self._valid(cycle, pose, vel, (0.0, 0.0, vth)):
            message = "TrajectoryPlannerROS: cannot turn to the goal's yaw without a collision"
            raise NoTrajectoryError(message)
        return Command(0.0, 0.0, vth)

    def _rotate_to_goal(self, pose: Pose, vel: Pose, goal_yaw: float) -> float:
        p = self._params
        diff = angle_diff(pose[2], goal_yaw)
        low = p.min_in_place_vel_theta
        if diff > 0:
            v = min(p.max_vel_theta, max(low, diff))
        else:
            v = max(p.min_vel_theta, min(-low, diff))
        step = p.acc_lim_theta * p.sim_period
        v = sign(v) * min(max(abs(v), abs(vel[2]) - step), abs(vel[2]) + step)
        v = sign(v) * min(math.sqrt(2 * p.acc_lim_theta * abs(diff)), abs(v))
        # the least in-place speed matters more than the acceleration limit
        if v > 0:
            return min(p.max_vel_theta, max(low, v))
        return max(p.min_vel_theta, min(-low, v))
