"""``dwa_local_planner/DWAPlannerROS``: the Dynamic Window Approach.

Each cycle samples (vx, vy, vth) on a grid inside the window the acceleration limits reach in one
controller period (``use_dwa``; else in ``sim_time``, accelerating along the rollout), drops
samples slower than both ``min_vel_trans`` and ``min_vel_theta`` or faster than
``max_vel_trans``, simulates each for ``sim_time`` and sums its critics' scaled costs:
oscillation (a sample that reverses a recent direction is invalid until the robot moved
``oscillation_reset_dist`` or turned ``oscillation_reset_angle``), obstacles (the footprint,
grown above ``scaling_speed`` up to ``max_scaling_factor``, must not meet an obstacle; costs
the highest cell cost met), the goal distance of a point ``forward_point_distance`` ahead of
the end, the path distance of that point (off near the goal), and the path and goal distances
of the end. Distances are in cells; the biases are scaled by the resolution. Once within
``xy_goal_tolerance`` (latched with ``latch_xy_goal_tolerance``) it stops and turns in place.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.nav.costmap import CostGrid
from belvedere.nav.local._base import (
    Command,
    NoTrajectoryError,
    angle_diff,
    as_path,
    slowed,
    stopped,
)
from belvedere.nav.local._maps import (
    DistanceMap,
    FootprintModel,
    clipped_cells,
    follow_plan,
    footprint_model,
    plan_cells,
    used_points_cost,
    wavefronts,
)
from belvedere.nav.local._params import DWAPlannerParams
from belvedere.nav.local._rollout import Rollouts, rollout, velocity_samples

__all__ = ["DWAPlannerROS"]

Floats = npt.NDArray[np.float64]
Bools = npt.NDArray[np.bool_]
Pose = tuple[float, float, float]


@dataclass
class _Cycle:
    grid: CostGrid
    model: FootprintModel
    path_map: DistanceMap
    goal_map: DistanceMap
    front_map: DistanceMap
    align: bool
    """Whether the forward point is kept on the path (off within forward_point_distance of
    the goal)."""
    plan: Floats


class _Oscillation:
    """base_local_planner's OscillationCostFunction: which directions are barred."""

    def __init__(self) -> None:
        self.reset()
        self.prev = np.zeros(3)

    def reset(self) -> None:
        self.forward_pos = self.forward_neg = False
        self.strafe_pos = self.strafe_neg = False
        self.rot_pos = self.rot_neg = False
        self.forward_pos_only = self.forward_neg_only = False
        self.strafe_pos_only = self.strafe_neg_only = False
        self.rot_pos_only = self.rot_neg_only = False

    def barred(self, v: Floats) -> Bools:
        """(S,) whether each (vx, vy, vth) row reverses a barred direction."""
        vx, vy, vth = v[:, 0], v[:, 1], v[:, 2]
        return (
            (self.forward_pos_only & (vx < 0))
            | (self.forward_neg_only & (vx > 0))
            | (self.strafe_pos_only & (vy < 0))
            | (self.strafe_neg_only & (vy > 0))
            | (self.rot_pos_only & (vth < 0))
            | (self.rot_neg_only & (vth > 0))
        )

    def _restricted(self) -> bool:
        return (
            self.forward_pos_only
            or self.forward_neg_only
            or self.strafe_pos_only
            or self.strafe_neg_only
            or self.rot_pos_only
            or self.rot_neg_only
        )

    def update(self, pose: Pose, v: Pose, min_vel_trans: float, dist: float, angle: float) -> None:
        if self._set_flags(v, min_vel_trans):
            self.prev = np.array(pose)
        if self._restricted():
            dx, dy = pose[0] - self.prev[0], pose[1] - self.prev[1]
            if dx * dx + dy * dy > dist * dist or abs(pose[2] - self.prev[2]) > angle:
                self.reset()

    def _set_flags(self, v: Pose, min_vel_trans: float) -> bool:
        vx, vy, vth = v
        flagged = False
        if vx < 0.0:
            if self.forward_pos:
                self.forward_neg_only = flagged = True
            self.forward_pos, self.forward_neg = False, True
        if vx > 0.0:
            if self.forward_neg:
                self.forward_pos_only = flagged = True
            self.forward_neg, self.forward_pos = False, True
        if abs(vx) <= min_vel_trans:
            if vy < 0:
                if self.strafe_pos:
                    self.strafe_neg_only = flagged = True
                self.strafe_pos, self.strafe_neg = False, True
            if vy > 0:
                if self.strafe_neg:
                    self.strafe_pos_only = flagged = True
                self.strafe_neg, self.strafe_pos = False, True
            if vth < 0:
                if self.rot_pos:
                    self.rot_neg_only = flagged = True
                self.rot_pos, self.rot_neg = False, True
            if vth > 0:
                if self.rot_neg:
                    self.rot_pos_only = flagged = True
                self.rot_neg, self.rot_pos = False, True
        return flagged


class DWAPlannerROS:
    """dwa_local_planner's DWAPlannerROS over plain arrays (see the module doc)."""

    name = "dwa_local_planner/DWAPlannerROS"

    def __init__(self, params: DWAPlannerParams | Mapping[str, Any] | None = None) -> None:
        if params is None or not isinstance(params, DWAPlannerParams):
            params = DWAPlannerParams.from_mapping(params or {})
        self._params = params
        self._plan: Floats = np.zeros((0, 3))
        self._latched = False
        self._rotating_to_goal = False
        self._oscillation = _Oscillation()
        self._model: FootprintModel | None = None

    @property
    def params(self) -> DWAPlannerParams:
        return self._params

    def set_plan(self, path: Floats) -> None:
        self._plan = as_path(path)
        self._oscillation.reset()
        self._latched = False

    def _position_reached(self, x: float, y: float) -> bool:
        """LatchedStopRotateController's isPositionReached (it latches either way)."""
        p = self._params
        if len(self._plan) == 0:
            return False
        gx, gy = self._plan[-1, 0], self._plan[-1, 1]
        if (p.latch_xy_goal_tolerance and self._latched) or math.hypot(
            gx - x, gy - y
        ) <= p.xy_goal_tolerance:
            self._latched = True
            return True
        return False

    def goal_reached(self, pose: Pose | Floats, velocity: Pose | Floats) -> bool:
        p = self._params
        if len(self._plan) == 0:
            return False
        x, y, yaw = (float(v) for v in pose)
        gx, gy, gyaw = (float(v) for v in self._plan[-1])
        if not (
            (p.latch_xy_goal_tolerance and self._latched)
            or math.hypot(gx - x, gy - y) <= p.xy_goal_tolerance
        ):
            return False
        if p.latch_xy_goal_tolerance:
            self._latched = True
        vel = (float(velocity[0]), float(velocity[1]), float(velocity[2]))
        return abs(angle_diff(yaw, gyaw)) <= p.yaw_goal_tolerance and stopped(
            vel, p.theta_stopped_vel, p.trans_stopped_vel
        )

    # -- one cycle --------------------------------------------------------------------------

    def compute(
        self, grid: CostGrid, pose: Pose | Floats, velocity: Pose | Floats, footprint: Floats
    ) -> Command:
        p = self._params
        x, y, yaw = (float(v) for v in pose)
        vel = (float(velocity[0]), float(velocity[1]), float(velocity[2]))
        local, self._plan = follow_plan(
            self._plan, grid, x, y, prune=p.prune_plan, planner="DWAPlannerROS"
        )
        cycle = self._prepare(grid, (x, y, yaw), footprint, local)
        if self._position_reached(x, y):
            return self._stop_and_rotate(cycle, (x, y, yaw), vel)
        samples = self._window((x, y, yaw), vel, local[-1])
        r = self._simulate((x, y, yaw), vel, samples)
        commanded = self._commanded(r, vel)
        cost = self._score(cycle, r, commanded)
        valid = np.flatnonzero(cost >= 0)
        if len(valid) == 0:
            message = (
                "DWAPlannerROS: no valid trajectory (every sample collides, leaves the local "
                "costmap, loses the path to the goal or oscillates)"
            )
            raise NoTrajectoryError(message)
        best = int(valid[np.argmin(cost[valid])])
        command = commanded[best]
        self._oscillation.update(
            (x, y, yaw),
            (float(command[0]), float(command[1]), float(command[2])),
            p.min_vel_trans,
            p.oscillation_reset_dist,
            p.oscillation_reset_angle,
        )
        return Command(float(command[0]), float(command[1]), float(command[2]), r.points(best))

    def _prepare(self, grid: CostGrid, pose: Pose, footprint: Floats, local: Floats) -> _Cycle:
        p = self._params
        model = self._model = footprint_model(self._model, footprint, grid.resolution)
        columns, rows = plan_cells(grid, local[:, :2])
        # the goal pulls the robot's nose, not its centre: the plan's end moved ahead along
        # the bearing from the robot to the goal
        gx, gy = float(local[-1, 0]), float(local[-1, 1])
        bearing = math.atan2(gy - pose[1], gx - pose[0])
        front = local[:, :2].copy()
        front[-1] += p.forward_point_distance * np.array([math.cos(bearing), math.sin(bearing)])
        fc, fr = plan_cells(grid, front)
        targets = [(columns, rows), (columns[-1:], rows[-1:])]
        same_goal = len(fc) and len(columns) and fc[-1] == columns[-1] and fr[-1] == rows[-1]
        if not same_goal:
            targets.append((fc[-1:], fr[-1:]))
        maps = wavefronts(grid, targets)
        path_map, goal_map = maps[0], maps[1]
        front_map = goal_map if same_goal else maps[2]
        far = math.hypot(gx - pose[0], gy - pose[1]) > p.forward_point_distance
        return _Cycle(grid, model, path_map, goal_map, front_map, far, local)

    # -- sampling and scoring ---------------------------------------------------------------

    def _window(self, pose: Pose, vel: Pose, goal: Floats) -> Floats:
        """The velocity samples (SimpleTrajectoryGenerator's initialise, in its order)."""
        p = self._params
        max_th, min_th = p.max_vel_theta, -p.max_vel_theta
        max_x, min_x, max_y, min_y = p.max_vel_x, p.min_vel_x, p.max_vel_y, p.min_vel_y
        acc = (p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta)
        reach = p.sim_period if p.use_dwa else p.sim_time
        high = [max_x, max_y, max_th]
        low = [min_x, min_y, min_th]
        if not p.use_dwa:
            # no point overshooting the plan's end within sim_time
            dist = math.hypot(float(goal[0]) - pose[0], float(goal[1]) - pose[1])
            high[0] = max(min(max_x, dist / p.sim_time), min_x)
            high[1] = max(min(max_y, dist / p.sim_time), min_y)
        axes = []
        for a in range(3):
            top = min(high[a], vel[a] + acc[a] * reach)
            bottom = max(low[a], vel[a] - acc[a] * reach)
            count = (p.vx_samples, p.vy_samples, p.vth_samples)[a]
            axes.append(velocity_samples(bottom, top, count))
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        vmag = np.hypot(grid[:, 0], grid[:, 1])
        eps = 1e-4
        too_slow = (
            (p.min_vel_trans >= 0)
            & (vmag + eps < p.min_vel_trans)
            & (p.min_vel_theta >= 0)
            & (np.abs(grid[:, 2]) + eps < p.min_vel_theta)
        )
        too_fast = (p.max_vel_trans >= 0) & (vmag - eps > p.max_vel_trans)
        keep = ~too_slow & ~too_fast & (self._steps(grid) > 0)
        return grid[keep]

    def _steps(self, samples: Floats) -> npt.NDArray[np.intp]:
        p = self._params
        vmag = np.hypot(samples[:, 0], samples[:, 1])
        return np.ceil(
            np.maximum(
                vmag * p.sim_time / p.sim_granularity,
                np.abs(samples[:, 2]) * p.sim_time / p.angular_sim_granularity,
            )
        ).astype(np.intp)

    def _simulate(self, pose: Pose, vel: Pose, samples: Floats) -> Rollouts:
        p = self._params
        return rollout(
            pose,
            vel,
            samples,
            np.maximum(self._steps(samples), 1),
            p.sim_time,
            (p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta),
            accelerate=not p.use_dwa,
            first_increment=2,
        )

    def _commanded(self, r: Rollouts, vel: Pose) -> Floats:
        """Each trajectory's command: its sample, or without ``use_dwa`` the velocity after
        the first step of acceleration towards it."""
        p = self._params
        if p.use_dwa:
            return r.samples
        acc = np.array([p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta])
        start = np.array(vel)
        delta = r.samples - start
        first: Floats = start + np.sign(delta) * np.minimum(np.abs(delta), acc * r.dt[:, None])
        return first

    def _score(self, cycle: _Cycle, r: Rollouts, velocities: Floats) -> Floats:
        """(S,) total cost, negative where a critic rejects the trajectory; ``velocities``
        are the trajectories' commands (what oscillation and footprint scaling look at)."""
        p = self._params
        grid = cycle.grid
        res = grid.resolution
        count = len(r.samples)
        used = r.used
        rows = np.arange(count)
        last = r.steps - 1
        total = np.zeros(count)
        bad = np.zeros(count, dtype=bool)
        bad |= self._oscillation.barred(velocities)

        ic, jc, inside = clipped_cells(grid, r.x, r.y)

        def grid_cost(dmap: DistanceMap, shift: float, stop_on_failure: bool) -> Floats:
            nonlocal bad
            if shift:
                i2, j2, ins = clipped_cells(
                    grid, r.x + shift * np.cos(r.yaw), r.y + shift * np.sin(r.yaw)
                )
            else:
                i2, j2, ins = ic, jc, inside
            values = dmap.dist[j2, i2]
            bad |= (used & ~ins).any(axis=1)
            if stop_on_failure:
                bad |= (used & (values >= dmap.obstacle_cost)).any(axis=1)
            end: Floats = values[rows, last]
            return end

        pdist = p.path_distance_bias * res
        gdist = p.goal_distance_bias * res
        if gdist:
            total += gdist * grid_cost(cycle.front_map, p.forward_point_distance, False)
        if pdist and cycle.align:
            total += pdist * grid_cost(cycle.path_map, p.forward_point_distance, False)
        if pdist:
            total += pdist * grid_cost(cycle.path_map, 0.0, True)
        if gdist:
            total += gdist * grid_cost(cycle.goal_map, 0.0, True)
        if p.twirling_scale:
            total += p.twirling_scale * np.abs(velocities[:, 2])
        if p.occdist_scale != 0:
            vmag = np.hypot(velocities[:, 0], velocities[:, 1])
            scale = np.ones(count)
            if p.max_vel_trans > p.scaling_speed:
                fast = vmag > p.scaling_speed
                ratio = (vmag - p.scaling_speed) / (p.max_vel_trans - p.scaling_speed)
                scale = np.where(fast, p.max_scaling_factor * ratio + 1.0, 1.0)
            grow = np.broadcast_to(scale[:, None], r.x.shape)
            # trajectories another critic rejected need no footprint
            alive = used & ~bad[:, None]
            fp_cost, fp_valid = used_points_cost(cycle.model, grid, r.x, r.y, r.yaw, alive, grow)
            centre = grid.costs[jc, ic].astype(np.float64)
            point = np.maximum(fp_cost, centre)
            bad |= (used & (~fp_valid | ~inside)).any(axis=1)
            point = np.where(used, point, 0.0)
            occ = point.sum(axis=1) if p.sum_scores else point.max(axis=1)
            total += p.occdist_scale * occ

        return np.where(bad, -1.0, total)

    # -- at the goal ------------------------------------------------------------------------

    def _valid(self, cycle: _Cycle, pose: Pose, vel: Pose, sample: Pose) -> bool:
        """DWAPlanner's checkTrajectory (with fresh oscillation flags): a sample the
        generator rejects leaves an empty trajectory, which every critic accepts."""
        samples = np.array([sample])
        if self._steps(samples)[0] == 0:
            return True
        saved = self._oscillation
        self._oscillation = _Oscillation()
        try:
            r = self._simulate(pose, vel, samples)
            return bool(self._score(cycle, r, self._commanded(r, vel))[0] >= 0)
        finally:
            self._oscillation = saved

    def _stop_and_rotate(self, cycle: _Cycle, pose: Pose, vel: Pose) -> Command:
        p = self._params
        goal_yaw = float(self._plan[-1, 2])
        diff = angle_diff(pose[2], goal_yaw)
        if abs(diff) <= p.yaw_goal_tolerance:
            self._rotating_to_goal = False
            return Command(0.0, 0.0, 0.0)
        period = p.sim_period
        if not self._rotating_to_goal and not stopped(
            vel, p.theta_stopped_vel, p.trans_stopped_vel
        ):
            cmd = slowed(vel, (p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta), period)
            if not self._valid(cycle, pose, vel, cmd):
                message = "DWAPlannerROS: cannot slow down at the goal without a collision"
                raise NoTrajectoryError(message)
            return Command(*cmd)
        self._rotating_to_goal = True
        v = min(p.max_vel_theta, max(p.min_vel_theta, abs(diff)))
        step = p.acc_lim_theta * period
        v = min(max(v, abs(vel[2]) - step), abs(vel[2]) + step)
        v = min(math.sqrt(2 * p.acc_lim_theta * abs(diff)), v)
        v = min(p.max_vel_theta, max(p.min_vel_theta, v))
        if diff < 0:
            v = -v
        if not self._valid(cycle, pose, vel, (0.0, 0.0, v)):
            message = "DWAPlannerROS: cannot turn to the goal's yaw without a collision"
            raise NoTrajectoryError(message)
        return Command(0.0, 0.0, v)
