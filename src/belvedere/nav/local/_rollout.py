"""Forward simulation of many velocity samples at once (the trajectory generators of
base_local_planner and dwa_local_planner), as (samples, steps) arrays."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

__all__ = ["Rollouts", "rollout", "velocity_samples"]

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.intp]
Bools = npt.NDArray[np.bool_]


@dataclass(frozen=True)
class Rollouts:
    """Trajectories of S samples, padded to the longest: point k of sample s is
    ``(x[s, k], y[s, k], yaw[s, k])`` where ``used[s, k]``."""

    samples: Floats
    """(S, 3) sampled velocities (vx, vy, vth): the command each trajectory stands for."""
    x: Floats
    y: Floats
    yaw: Floats
    used: Bools
    dt: Floats
    """(S,) time step of each sample."""
    steps: Ints
    """(S,) points of each sample."""

    def points(self, s: int) -> Floats:
        """(n, 3) poses of sample ``s``."""
        n = int(self.steps[s])
        return np.column_stack([self.x[s, :n], self.y[s, :n], self.yaw[s, :n]])


def _approach(start: Floats, target: Floats, reach: Floats) -> Floats:
    """``start`` moved towards ``target`` by at most ``reach`` (computeNewVelocity)."""
    delta = target - start
    moved: Floats = start + np.sign(delta) * np.minimum(np.abs(delta), reach)
    return moved


def rollout(
    pose: tuple[float, float, float],
    velocity: tuple[float, float, float],
    samples: Floats,
    steps: Ints,
    sim_time: float,
    acc_lim: tuple[float, float, float],
    *,
    accelerate: bool,
    first_increment: int,
) -> Rollouts:
    """Simulate each sample for ``sim_time`` in ``steps[s]`` equal steps from the pose.

    With ``accelerate`` the velocity moves from ``velocity`` towards the sample by the
    acceleration limits each step (Trajectory Rollout; DWA without ``use_dwa``), the m-th
    position update using ``m - 1 + first_increment`` steps of acceleration; otherwise the
    sample velocity holds from the start (DWA). Positions integrate as both planners do:
    ``x += (vx cos yaw - vy sin yaw) dt``, then ``yaw += vth dt``."""
    samples = np.asarray(samples, dtype=np.float64).reshape(-1, 3)
    count = len(samples)
    steps = np.maximum(np.asarray(steps, dtype=np.intp), 1)
    longest = int(steps.max()) if count else 1
    dt = sim_time / steps
    k = np.arange(longest)
    used = k[None, :] < steps[:, None]
    # velocities of the position updates that lead to points 1..longest-1
    m = np.arange(1, longest)
    vel: list[Floats] = []
    for axis in range(3):
        target = samples[:, axis : axis + 1]
        if accelerate:
            reach = acc_lim[axis] * dt[:, None] * (m[None, :] - 1 + first_increment)
            start = np.full_like(target, velocity[axis])
            vel.append(_approach(start, target, reach))
        else:
            vel.append(np.broadcast_to(target, (count, longest - 1)))
    vx, vy, vth = vel
    step_dt = dt[:, None]
    yaw = np.empty((count, longest))
    yaw[:, 0] = pose[2]
    yaw[:, 1:] = pose[2] + np.cumsum(vth * step_dt, axis=1)
    heading = yaw[:, :-1]
    cos, sin = np.cos(heading), np.sin(heading)
    x = np.empty((count, longest))
    y = np.empty((count, longest))
    x[:, 0] = pose[0]
    y[:, 0] = pose[1]
    x[:, 1:] = pose[0] + np.cumsum((vx * cos - vy * sin) * step_dt, axis=1)
    y[:, 1:] = pose[1] + np.cumsum((vx * sin + vy * cos) * step_dt, axis=1)
    return Rollouts(samples, x, y, yaw, used, dt, steps)


def velocity_samples(low: float, high: float, count: int) -> Floats:
    """dwa_local_planner's VelocityIterator: ``count`` (at least 2) evenly spaced values from
    ``low`` to ``high``, with 0 added where the range crosses it; one value when
    ``low == high``."""
    if low == high:
        return np.array([low])
    values = np.linspace(low, high, max(2, count))
    if low < 0.0 < high and not np.any(values == 0.0):
        values = np.sort(np.append(values, 0.0))
    return values
