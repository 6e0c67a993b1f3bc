"""The local planners' parameters, with ROS's names, old names and defaults.

Each planner reads its ``~<name>/`` namespace as a plain mapping (the caller also puts
``controller_frequency`` there, which the ROS planners find by an upward search from their
namespace). Names ROS renamed are read under both: the new one wins when both are set.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from belvedere.nav._params import ParamReader, read_fields

__all__ = ["DWAPlannerParams", "TrajectoryPlannerParams"]

_DEFAULT_Y_VELS = (-0.3, -0.1, 0.1, 0.3)


def _sim_period(read: ParamReader) -> float:
    """The controller period the dynamic window spans: 1/controller_frequency, or 0.05 s
    when it is unset or not positive (as both ROS planners fall back to 20 Hz)."""
    frequency = read.number(0.0, "controller_frequency")
    return 1.0 / frequency if frequency > 0 else 0.05


_TRAJECTORY_ALIASES = {
    "acc_lim_theta": ("acc_lim_th",),
    "min_in_place_vel_theta": ("min_in_place_rotational_vel",),
    "escape_vel": ("backup_vel",),
    "path_distance_bias": ("pdist_scale",),
    "goal_distance_bias": ("gdist_scale",),
}
"""Older names ROS still reads (the course and rbx1 use some)."""

_DWA_ALIASES = {
    "max_vel_trans": ("max_trans_vel",),
    "min_vel_trans": ("min_trans_vel",),
    "max_vel_theta": ("max_rot_vel",),
    "min_vel_theta": ("min_rot_vel",),
    "acc_lim_theta": ("acc_lim_th",),
    "acc_lim_trans": ("acc_limit_trans",),
    "theta_stopped_vel": ("rot_stopped_vel",),
}


def _at_least_one_sample(fields: dict[str, Any]) -> dict[str, Any]:
    """Sample counts below one are one, as the planners clamp them."""
    return {k: max(1, v) if k.endswith("_samples") else v for k, v in fields.items()}


def _at_least(name: str, value: float, low: float) -> None:
    if value < low:
        message = f"parameter {name} must be at least {low:g}, got {value:g}"
        raise ValueError(message)


def _check_shared(params: TrajectoryPlannerParams | DWAPlannerParams, *axes: str) -> None:
    """The checks both planners make: positive simulation steps, limits and tolerances not
    negative, and for each of ``axes`` ``max_vel_<axis>`` not below ``min_vel_<axis>``."""
    for name in ("sim_time", "sim_granularity", "angular_sim_granularity"):
        if getattr(params, name) <= 0:
            message = f"parameter {name} must be positive, got {getattr(params, name):g}"
            raise ValueError(message)
    for name in ("acc_lim_x", "acc_lim_y", "acc_lim_theta", "xy_goal_tolerance"):
        _at_least(name, getattr(params, name), 0.0)
    _at_least("yaw_goal_tolerance", params.yaw_goal_tolerance, 0.0)
    for axis in axes:
        high, low = getattr(params, f"max_vel_{axis}"), getattr(params, f"min_vel_{axis}")
        if high < low:
            message = (
                f"parameters max_vel_{axis} ({high:g}) and min_vel_{axis} ({low:g}): "
                "the maximum is below the minimum"
            )
            raise ValueError(message)


@dataclass(frozen=True)
class TrajectoryPlannerParams:
    """``base_local_planner/TrajectoryPlannerROS``'s parameters (ROS defaults)."""

    acc_lim_x: float = 2.5
    acc_lim_y: float = 2.5
    acc_lim_theta: float = 3.2
    """Also read as ``acc_lim_th`` (the older name, which rbx1 uses)."""
    max_vel_x: float = 0.5
    min_vel_x: float = 0.1
    max_vel_theta: float = 1.0
    min_vel_theta: float = -1.0
    """A set ``max_rotational_vel`` (the older name) gives both: ``±max_rotational_vel``."""
    min_in_place_vel_theta: float = 0.4
    escape_vel: float = -0.1
    """Also read as ``backup_vel``; ``escape_vel`` wins."""
    holonomic_robot: bool = True
    y_vels: tuple[float, ...] = _DEFAULT_Y_VELS
    xy_goal_tolerance: float = 0.10
    yaw_goal_tolerance: float = 0.05
    latch_xy_goal_tolerance: bool = False
    sim_time: float = 1.0
    sim_granularity: float = 0.025
    angular_sim_granularity: float = 0.025
    """Defaults to ``sim_granularity``."""
    vx_samples: int = 3
    vtheta_samples: int = 20
    controller_frequency: float = 20.0
    sim_period: float = 0.05
    """1/controller_frequency: how far the dynamic window reaches (``dwa``)."""
    meter_scoring: bool = False
    path_distance_bias: float = 0.6
    """Also read as ``pdist_scale`` (the older name the course and rbx1 use)."""
    goal_distance_bias: float = 0.8
    """Also read as ``gdist_scale``."""
    occdist_scale: float = 0.01
    heading_lookahead: float = 0.325
    heading_scoring: bool = False
    heading_scoring_timestep: float = 0.8
    dwa: bool = True
    simple_attractor: bool = False
    escape_reset_dist: float = 0.10
    escape_reset_theta: float = math.pi / 4
    oscillation_reset_dist: float = 0.05
    prune_plan: bool = True
    stop_time_buffer: float = 0.2
    """Read and kept; TrajectoryPlanner's use of it is commented out in ROS too."""

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> TrajectoryPlannerParams:
        """The parameters from ``name → value``; unknown names are ignored as ROS does."""
        read = ParamReader(values)
        sim_granularity = read.number(0.025, "sim_granularity")
        given: dict[str, Any] = {
            "angular_sim_granularity": read.number(sim_granularity, "angular_sim_granularity"),
            "sim_period": _sim_period(read),
        }
        if read.has("max_rotational_vel"):
            top = read.number(1.0, "max_rotational_vel")
            given.update(max_vel_theta=top, min_vel_theta=-top)
        params = cls(**_at_least_one_sample(read_fields(cls, read, _TRAJECTORY_ALIASES, given)))
        params.check()
        return params

    def check(self) -> None:
        """Raise ``ValueError`` for values the planner cannot work with."""
        _check_shared(self, "x", "theta")


@dataclass(frozen=True)
class DWAPlannerParams:
    """``dwa_local_planner/DWAPlannerROS``'s parameters (ROS defaults)."""

    max_vel_trans: float = 0.55
    """Also read as ``max_trans_vel`` (the name before Kinetic)."""
    min_vel_trans: float = 0.1
    """Also read as ``min_trans_vel``."""
    max_vel_x: float = 0.55
    min_vel_x: float = 0.0
    max_vel_y: float = 0.1
    min_vel_y: float = -0.1
    max_vel_theta: float = 1.0
    """Also read as ``max_rot_vel``; samples span ``±max_vel_theta``."""
    min_vel_theta: float = 0.4
    """Also read as ``min_rot_vel``: the least |rotation| of a sample that does not translate
    by ``min_vel_trans`` either."""
    acc_lim_x: float = 2.5
    acc_lim_y: float = 2.5
    acc_lim_theta: float = 3.2
    acc_lim_trans: float = 0.1
    """Read and kept; the noetic trajectory generator does not use it either."""
    prune_plan: bool = False
    xy_goal_tolerance: float = 0.1
    yaw_goal_tolerance: float = 0.1
    trans_stopped_vel: float = 0.1
    theta_stopped_vel: float = 0.1
    latch_xy_goal_tolerance: bool = False
    sim_time: float = 1.7
    sim_granularity: float = 0.025
    angular_sim_granularity: float = 0.1
    path_distance_bias: float = 32.0
    goal_distance_bias: float = 24.0
    occdist_scale: float = 0.01
    twirling_scale: float = 0.0
    stop_time_buffer: float = 0.2
    oscillation_reset_dist: float = 0.05
    oscillation_reset_angle: float = 0.2
    forward_point_distance: float = 0.325
    scaling_speed: float = 0.25
    max_scaling_factor: float = 0.2
    vx_samples: int = 3
    vy_samples: int = 10
    vth_samples: int = 20
    use_dwa: bool = True
    sum_scores: bool = False
    controller_frequency: float = 20.0
    sim_period: float = 0.05

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> DWAPlannerParams:
        """The parameters from ``name → value``; unknown names are ignored as ROS does."""
        read = ParamReader(values)
        given = {"sim_period": _sim_period(read)}
        params = cls(**_at_least_one_sample(read_fields(cls, read, _DWA_ALIASES, given)))
        params.check()
        return params

    def check(self) -> None:
        """Raise ``ValueError`` for values the planner cannot work with."""
        # min_vel_theta is the least |rotation| here, not the bottom of a range
        _check_shared(self, "x", "y")
