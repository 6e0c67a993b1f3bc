"""What every local planner shares: its command, its failure and its interface."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import numpy.typing as npt

from belvedere.nav.costmap import CostGrid

__all__ = [
    "Command",
    "LocalPlanner",
    "NoTrajectoryError",
    "angle_diff",
    "as_path",
    "sign",
    "slowed",
    "stopped",
]

Floats = npt.NDArray[np.float64]


class NoTrajectoryError(ValueError):
    """The planner found no velocity command it may send (every sampled trajectory would
    collide or lose the path, no plan, or the goal rotation is blocked); move_base then stops
    the robot and, after ``controller_patience``, runs its recovery behaviours."""


def _empty_plan() -> Floats:
    return np.zeros((0, 3))


@dataclass(frozen=True)
class Command:
    """A velocity command in the robot's frame and the trajectory it was chosen for."""

    vx: float
    vy: float
    vth: float
    local_plan: Floats = field(default_factory=_empty_plan)
    """(M, 3) poses (x, y, yaw) in the grid's frame; empty while stopping or turning at the
    goal."""


class LocalPlanner(Protocol):
    """nav_core's BaseLocalPlanner over plain arrays."""

    name: str
    """The plugin name, e.g. ``dwa_local_planner/DWAPlannerROS``."""

    @property
    def params(self) -> Any:
        """The parsed parameters (with ``controller_frequency`` and ``sim_period``)."""

    def set_plan(self, path: Floats) -> None:
        """Follow this global plan ((N, 3) poses in the grid's frame) from now on."""

    def compute(
        self,
        grid: CostGrid,
        pose: tuple[float, float, float] | Floats,
        velocity: tuple[float, float, float] | Floats,
        footprint: Floats,
    ) -> Command:
        """One control cycle: the command for the robot at ``pose`` moving at ``velocity``
        (robot frame, as odometry gives it) with ``footprint`` ((K, 2), robot frame).

        Raises:
            NoTrajectoryError: when no command is valid."""

    def goal_reached(
        self,
        pose: tuple[float, float, float] | Floats,
        velocity: tuple[float, float, float] | Floats,
    ) -> bool:
        """Whether the goal (the plan's last pose) is reached within the tolerances."""


def as_path(path: Floats) -> Floats:
    """The plan as a float (N, 3) array; a wrong shape raises ``ValueError``."""
    array = np.asarray(path, dtype=np.float64)
    if array.ndim != 2 or array.shape[1] != 3:
        message = f"a plan is an (N, 3) array of poses (x, y, yaw), got shape {array.shape}"
        raise ValueError(message)
    return array.copy()


def angle_diff(start: float, end: float) -> float:
    """The shortest signed rotation from ``start`` to ``end``
    (angles::shortest_angular_distance)."""
    return math.remainder(end - start, math.tau)


def stopped(velocity: tuple[float, float, float], rot_stopped: float, trans_stopped: float) -> bool:
    """base_local_planner's ``stopped``: every velocity component within its threshold."""
    vx, vy, vth = velocity
    return abs(vth) <= rot_stopped and abs(vx) <= trans_stopped and abs(vy) <= trans_stopped


def sign(value: float) -> float:
    """-1 for negative values, else 1 (as base_local_planner's sign, so 0 counts as positive)."""
    return -1.0 if value < 0 else 1.0


def slowed(
    velocity: tuple[float, float, float], acc_lim: tuple[float, float, float], period: float
) -> tuple[float, float, float]:
    """Each component brought towards zero by its acceleration limit over one controller
    period, never past it (base_local_planner's stopWithAccLimits)."""
    vx, vy, vth = velocity
    return (
        sign(vx) * max(0.0, abs(vx) - acc_lim[0] * period),
        sign(vy) * max(0.0, abs(vy) - acc_lim[1] * period),
        sign(vth) * max(0.0, abs(vth) - acc_lim[2] * period),
    )
