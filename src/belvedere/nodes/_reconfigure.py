"""The reconfigurable parameters of belvedere's navigation nodes, with the names, types,
levels, defaults and ranges of ROS's ``.cfg`` files (move_base's MoveBase.cfg,
dwa_local_planner's DWAPlanner.cfg with base_local_planner's generic limits,
base_local_planner's BaseLocalPlanner.cfg, amcl's AMCL.cfg, costmap_2d's Costmap2D.cfg and its
plugins' files), for rqt_reconfigure and dynparam.

Omitted: each file's ``restore_defaults`` and the parameters belvedere's nodes do not change
while running (a costmap's size, resolution, origin and footprint).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import fields, replace
from typing import Any, Final, TypeVar

from belvedere.ros1.dynamic_reconfigure._description import (
    Description,
    Group,
    Param,
    enum_edit_method,
)

__all__ = [
    "AMCL",
    "COSTMAP",
    "DWA_PLANNER",
    "GENERIC_LAYER",
    "INFLATION_LAYER",
    "MOVE_BASE",
    "OBSTACLE_LAYER",
    "TRAJECTORY_PLANNER",
    "current",
    "replaced",
]

_Row = tuple[Any, ...]
T = TypeVar("T")

_INF: Final = math.inf


def _table(name: str, rows: list[_Row]) -> Description:
    params = [Param.make(*row) for row in rows]
    constants: dict[str, Any] = {}
    for p in params:
        constants.update({n: v for v, n in p.enum.items()})
    return Description(name, Group("Default", params=params), constants)


def _enum(kind: str, options: list[tuple[str, Any, str]], about: str) -> str:
    return enum_edit_method(
        [{"name": n, "type": kind, "value": v, "description": d} for n, v, d in options], about
    )


MOVE_BASE: Final = _table(
    "MoveBase",
    [
        ("base_global_planner", "str", 0, "the global planner plugin", "navfn/NavfnROS"),
        (
            "base_local_planner",
            "str",
            0,
            "the local planner plugin",
            "base_local_planner/TrajectoryPlannerROS",
        ),
        ("planner_frequency", "double", 0, "replanning rate while controlling, Hz", 0.0, 0, 100),
        ("controller_frequency", "double", 0, "control loop rate, Hz", 20.0, 0, 100),
        ("planner_patience", "double", 0, "seconds without a plan before recovery", 5.0, 0, 100),
        (
            "controller_patience",
            "double",
            0,
            "seconds without a command before recovery",
            5.0,
            0,
            100,
        ),
        ("max_planning_retries", "int", 0, "planning attempts before recovery", -1, -1, 1000),
        ("conservative_reset_dist", "double", 0, "clearing distance, m", 3.0, 0, 50),
        ("recovery_behavior_enabled", "bool", 0, "run recovery behaviours", True),
        ("clearing_rotation_allowed", "bool", 0, "turn in place while recovering", True),
        ("shutdown_costmaps", "bool", 0, "stop the costmaps while idle", False),
        ("oscillation_timeout", "double", 0, "seconds of oscillation before recovery", 0.0, 0, 60),
        ("oscillation_distance", "double", 0, "motion that ends an oscillation, m", 0.5, 0, 10),
    ],
)

_LIMITS: Final[list[_Row]] = [
    ("max_vel_trans", "double", 0, "fastest translation, m/s", 0.55, 0, _INF),
    ("min_vel_trans", "double", 0, "slowest translation, m/s", 0.1, 0, _INF),
    ("max_vel_x", "double", 0, "fastest x velocity, m/s", 0.55, -_INF, _INF),
    ("min_vel_x", "double", 0, "slowest x velocity, m/s", 0.0, -_INF, _INF),
    ("max_vel_y", "double", 0, "fastest y velocity, m/s", 0.1, -_INF, _INF),
    ("min_vel_y", "double", 0, "slowest y velocity, m/s", -0.1, -_INF, _INF),
    ("max_vel_theta", "double", 0, "fastest rotation, rad/s", 1.0, 0, _INF),
    ("min_vel_theta", "double", 0, "slowest rotation, rad/s", 0.4, 0, _INF),
    ("acc_lim_x", "double", 0, "x acceleration limit, m/s²", 2.5, 0, 20.0),
    ("acc_lim_y", "double", 0, "y acceleration limit, m/s²", 2.5, 0, 20.0),
    ("acc_lim_theta", "double", 0, "rotational acceleration limit, rad/s²", 3.2, 0, 20.0),
    ("acc_lim_trans", "double", 0, "translational acceleration limit, m/s²", 0.1, 0, _INF),
    ("prune_plan", "bool", 0, "follow the plan from its closest point", False),
    ("xy_goal_tolerance", "double", 0, "goal distance tolerance, m", 0.1, -_INF, _INF),
    ("yaw_goal_tolerance", "double", 0, "goal heading tolerance, rad", 0.1, -_INF, _INF),
    ("trans_stopped_vel", "double", 0, "stopped below this translation, m/s", 0.1, -_INF, _INF),
    ("theta_stopped_vel", "double", 0, "stopped below this rotation, rad/s", 0.1, -_INF, _INF),
]

DWA_PLANNER: Final = _table(
    "DWAPlanner",
    [
        *_LIMITS,
        ("sim_time", "double", 0, "trajectory rollout time, s", 1.7, 0, _INF),
        ("sim_granularity", "double", 0, "collision check step, m", 0.025, 0, _INF),
        ("angular_sim_granularity", "double", 0, "collision check step, rad", 0.1, 0, _INF),
        ("path_distance_bias", "double", 0, "weight of staying on the path", 0.6, 0, _INF),
        ("goal_distance_bias", "double", 0, "weight of reaching the goal", 0.8, 0, _INF),
        ("occdist_scale", "double", 0, "weight of avoiding obstacles", 0.01, 0, _INF),
        ("twirling_scale", "double", 0, "weight of heading changes", 0.0, 0, _INF),
        ("stop_time_buffer", "double", 0, "stopping time before a collision, s", 0.2, 0, _INF),
        ("oscillation_reset_dist", "double", 0, "travel that resets oscillation, m", 0.05, 0, _INF),
        ("oscillation_reset_angle", "double", 0, "turn that resets oscillation, rad", 0.2, 0, _INF),
        ("forward_point_distance", "double", 0, "extra scoring point ahead, m", 0.325, -_INF, _INF),
        ("scaling_speed", "double", 0, "speed where footprint scaling starts, m/s", 0.25, 0, _INF),
        ("max_scaling_factor", "double", 0, "largest footprint scaling", 0.2, 0, _INF),
        ("vx_samples", "int", 0, "x velocity samples", 3, 1, 2**31 - 1),
        ("vy_samples", "int", 0, "y velocity samples", 10, 1, 2**31 - 1),
        ("vth_samples", "int", 0, "rotational velocity samples", 20, 1, 2**31 - 1),
    ],
)

TRAJECTORY_PLANNER: Final = _table(
    "BaseLocalPlanner",
    [
        ("acc_lim_x", "double", 0, "x acceleration limit, m/s²", 2.5, 0, 20.0),
        ("acc_lim_y", "double", 0, "y acceleration limit, m/s²", 2.5, 0, 20.0),
        ("acc_lim_theta", "double", 0, "rotational acceleration limit, rad/s²", 3.2, 0, 20.0),
        ("max_vel_x", "double", 0, "fastest x velocity, m/s", 0.55, 0, 20.0),
        ("min_vel_x", "double", 0, "slowest x velocity, m/s", 0.0, 0, 20.0),
        ("max_vel_theta", "double", 0, "fastest rotation, rad/s", 1.0, 0, 20.0),
        ("min_vel_theta", "double", 0, "slowest rotation, rad/s", -1.0, -20.0, 0.0),
        ("min_in_place_vel_theta", "double", 0, "slowest turn in place, rad/s", 0.4, 0, 20.0),
        ("sim_time", "double", 0, "trajectory rollout time, s", 1.7, 0, 10),
        ("sim_granularity", "double", 0, "collision check step, m", 0.025, 0, 5),
        (
            "angular_sim_granularity",
            "double",
            0,
            "collision check step, rad",
            0.025,
            0,
            math.pi / 2,
        ),
        ("path_distance_bias", "double", 0, "weight of staying on the path", 0.6, 0, 5),
        ("goal_distance_bias", "double", 0, "weight of reaching the goal", 0.8, 0, 5),
        ("occdist_scale", "double", 0, "weight of avoiding obstacles", 0.01, 0, 5),
        ("oscillation_reset_dist", "double", 0, "travel that resets oscillation, m", 0.05, 0, 5),
        ("escape_reset_dist", "double", 0, "travel that ends an escape, m", 0.10, 0, 5),
        ("escape_reset_theta", "double", 0, "turn that ends an escape, rad", math.pi / 2, 0, 5),
        ("vx_samples", "int", 0, "x velocity samples", 20, 1, 300),
        ("vtheta_samples", "int", 0, "rotational velocity samples", 20, 1, 300),
        ("heading_lookahead", "double", 0, "look-ahead for heading scoring, m", 0.325, 0, 5),
        ("holonomic_robot", "bool", 0, "the base moves sideways", True),
        ("escape_vel", "double", 0, "velocity while backing up, m/s", -0.1, -2, 2),
        ("dwa", "bool", 0, "use the dynamic window", False),
        ("heading_scoring", "bool", 0, "score by heading", False),
        ("heading_scoring_timestep", "double", 0, "heading scoring look-ahead, s", 0.1, 0, 1),
        ("simple_attractor", "bool", 0, "attract straight to the goal", False),
    ],
)

AMCL: Final = _table(
    "AMCL",
    [
        ("min_particles", "int", 0, "fewest particles", 100, 0, 1000),
        ("max_particles", "int", 0, "most particles", 5000, 0, 10000),
        ("kld_err", "double", 0, "KLD sampling error", 0.01, 0, 1),
        ("kld_z", "double", 0, "KLD sampling quantile", 0.99, 0, 1),
        ("update_min_d", "double", 0, "travel before a filter update, m", 0.2, 0, 5),
        (
            "update_min_a",
            "double",
            0,
            "turn before a filter update, rad",
            math.pi / 6,
            0,
            2 * math.pi,
        ),
        ("resample_interval", "int", 0, "updates between resamplings", 2, 0, 20),
        ("transform_tolerance", "double", 0, "future-dating of the transform, s", 0.1, 0, 2),
        ("recovery_alpha_slow", "double", 0, "slow average decay (0: off)", 0.0, 0, 0.5),
        ("recovery_alpha_fast", "double", 0, "fast average decay (0: off)", 0.0, 0, 1),
        ("do_beamskip", "bool", 0, "skip beams most particles disagree with", False),
        ("beam_skip_distance", "double", 0, "beam skip distance, m", 0.5, 0, 2),
        ("beam_skip_threshold", "double", 0, "beam skip ratio", 0.3, 0, 1),
        ("tf_broadcast", "bool", 0, "publish map → odom", True),
        (
            "gui_publish_rate",
            "double",
            0,
            "particle cloud rate, Hz (-1: every update)",
            -1.0,
            -1,
            100,
        ),
        ("save_pose_rate", "double", 0, "pose saving rate, Hz", 0.5, -1, 10),
        ("use_map_topic", "bool", 0, "subscribe to the map", False),
        ("first_map_only", "bool", 0, "keep the first map only", False),
        ("laser_min_range", "double", 0, "shortest range used, m (-1: the scan's)", -1.0, -1, 1000),
        ("laser_max_range", "double", 0, "longest range used, m (-1: the scan's)", -1.0, -1, 1000),
        ("laser_max_beams", "int", 0, "beams used per scan", 30, 0, 250),
        ("laser_z_hit", "double", 0, "weight of the hit model", 0.95, 0, 1),
        ("laser_z_short", "double", 0, "weight of the short model", 0.1, 0, 1),
        ("laser_z_max", "double", 0, "weight of the max-range model", 0.05, 0, 1),
        ("laser_z_rand", "double", 0, "weight of the random model", 0.05, 0, 1),
        ("laser_sigma_hit", "double", 0, "hit model deviation, m", 0.2, 0, 10),
        ("laser_lambda_short", "double", 0, "short model decay", 0.1, 0, 10),
        ("laser_likelihood_max_dist", "double", 0, "likelihood field reach, m", 2.0, 0, 20),
        (
            "laser_model_type",
            "str",
            0,
            "laser model",
            "likelihood_field",
            None,
            None,
            _enum(
                "str",
                [
                    ("beam_const", "beam", "beam model"),
                    ("likelihood_field_const", "likelihood_field", "likelihood field model"),
                    ("likelihood_field_prob_const", "likelihood_field_prob", "with beam skip"),
                ],
                "laser models",
            ),
        ),
        (
            "odom_model_type",
            "str",
            0,
            "odometry model",
            "diff",
            None,
            None,
            _enum(
                "str",
                [
                    ("diff_const", "diff", "differential drive"),
                    ("omni_const", "omni", "omnidirectional"),
                    ("diff_corrected_const", "diff-corrected", "corrected differential"),
                    ("omni_corrected_const", "omni-corrected", "corrected omnidirectional"),
                ],
                "odometry models",
            ),
        ),
        ("odom_alpha1", "double", 0, "rotation noise from rotation", 0.2, 0, 10),
        ("odom_alpha2", "double", 0, "rotation noise from translation", 0.2, 0, 10),
        ("odom_alpha3", "double", 0, "translation noise from translation", 0.2, 0, 10),
        ("odom_alpha4", "double", 0, "translation noise from rotation", 0.2, 0, 10),
        ("odom_alpha5", "double", 0, "translation-like noise (omni)", 0.2, 0, 10),
        ("odom_frame_id", "str", 0, "odometry frame", "odom"),
        ("base_frame_id", "str", 0, "robot base frame", "base_link"),
        ("global_frame_id", "str", 0, "map frame", "map"),
    ],
)


COSTMAP: Final = _table(
    "Costmap2D",
    [
        ("transform_tolerance", "double", 0, "tolerated age of the robot's pose, s", 0.3, 0, 10),
        ("update_frequency", "double", 0, "update rate, Hz", 5.0, 0, 100),
        ("publish_frequency", "double", 0, "publishing rate, Hz", 0.0, 0, 100),
    ],
)

_ENABLED: Final[_Row] = ("enabled", "bool", 0, "apply this layer", True)

GENERIC_LAYER: Final = _table("GenericPlugin", [_ENABLED])

INFLATION_LAYER: Final = _table(
    "InflationPlugin",
    [
        _ENABLED,
        ("cost_scaling_factor", "double", 0, "decay of inflated costs", 10.0, 0, 100),
        ("inflation_radius", "double", 0, "reach of inflated costs, m", 0.55, 0, 50),
        ("inflate_unknown", "bool", 0, "inflate into unknown cells", False),
    ],
)

OBSTACLE_LAYER: Final = _table(
    "ObstaclePlugin",
    [
        _ENABLED,
        ("footprint_clearing_enabled", "bool", 0, "clear the robot's footprint", True),
        ("max_obstacle_height", "double", 0, "tallest obstacle marked, m", 2.0, 0, 50),
        (
            "combination_method",
            "int",
            0,
            "how the layer combines into the master",
            1,
            None,
            None,
            _enum(
                "int",
                [
                    ("Overwrite", 0, "overwrite values"),
                    ("Maximum", 1, "the maximum of the values"),
                    ("Nothing", 99, "leave the master as it is"),
                ],
                "combination methods",
            ),
        ),
    ],
)


def current(description: Description, *sources: object) -> dict[str, Any]:
    """The values a node runs with, for the parameters of ``description`` its ``sources``
    (parameter dataclasses) hold."""
    out: dict[str, Any] = {}
    for p in description.params():
        for source in sources:
            if hasattr(source, p.name):
                out[p.name] = getattr(source, p.name)
                break
    return out


def replaced(params: T, config: Mapping[str, Any]) -> T:
    """``params`` (a dataclass) with the values of ``config`` it has fields for."""
    names = {f.name for f in fields(params)}  # type: ignore[arg-type]
    return replace(params, **{k: v for k, v in config.items() if k in names})  # type: ignore[type-var]
