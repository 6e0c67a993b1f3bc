"""The local planners' parameters: ROS's names, old names and defaults, as the course's and
rbx1's YAML files set them."""

from __future__ import annotations

import math
from typing import Any

import pytest
import yaml

from belvedere.nav._plugins import UnknownPluginError
from belvedere.nav.local import (
    LOCAL_PLANNERS,
    DWAPlannerParams,
    DWAPlannerROS,
    TrajectoryPlannerParams,
    TrajectoryPlannerROS,
    make_local_planner,
)

# The values of mbot_navigation/config/mbot/base_local_planner_params.yaml (the course's)
COURSE_YAML = """\
controller_frequency: 3.0
recovery_behavior_enabled: false
clearing_rotation_allowed: false

TrajectoryPlannerROS:
   max_vel_x: 0.5
   min_vel_x: 0.1
   max_vel_y: 0.0  # zero for a differential drive robot
   min_vel_y: 0.0
   max_vel_theta: 1.0
   min_vel_theta: -1.0
   min_in_place_vel_theta: 0.5
   escape_vel: -0.1
   acc_lim_x: 1.5
   acc_lim_y: 0.0 # zero for a differential drive robot
   acc_lim_theta: 1.2

   holonomic_robot: false
   yaw_goal_tolerance: 0.1 # about 6 degrees
   xy_goal_tolerance: 0.1  # 10 cm
   latch_xy_goal_tolerance: false
   pdist_scale: 0.9
   gdist_scale: 0.6
   meter_scoring: true

   heading_lookahead: 0.325
   heading_scoring: false
   heading_scoring_timestep: 0.8
   occdist_scale: 0.1
   oscillation_reset_dist: 0.05
   publish_cost_grid_pc: false
   prune_plan: true

   sim_time: 1.0
   sim_granularity: 0.025
   angular_sim_granularity: 0.025
   vx_samples: 8
   vy_samples: 0 # zero for a differential drive robot
   vtheta_samples: 20
   dwa: true
   simple_attractor: false
"""

# The values of rbx1_nav/config/fake/base_local_planner_params.yaml
RBX1_YAML = """\
controller_frequency: 3.0
recovery_behavior_enabled: false
clearing_rotation_allowed: false

TrajectoryPlannerROS:
   max_vel_x: 0.5
   min_vel_x: 0.1
   max_vel_y: 0.0  # zero for a differential drive robot
   min_vel_y: 0.0
   max_rotational_vel: 1.0
   min_in_place_vel_theta: 0.4
   escape_vel: -0.1
   acc_lim_x: 1.5
   acc_lim_y: 0.0  # zero for a differential drive robot
   acc_lim_th: 1.2

   holonomic_robot: false
   yaw_goal_tolerance: 0.1 # about 6 degrees
   xy_goal_tolerance: 0.05  # 5 cm
   latch_xy_goal_tolerance: false
   pdist_scale: 0.4
   gdist_scale: 0.8
   meter_scoring: true

   heading_lookahead: 0.325
   heading_scoring: false
   heading_scoring_timestep: 0.8
   occdist_scale: 0.05
   oscillation_reset_dist: 0.05
   publish_cost_grid_pc: false
   prune_plan: true

   sim_time: 1.0
   sim_granularity: 0.05
   angular_sim_granularity: 0.1
   vx_samples: 8
   vy_samples: 0  # zero for a differential drive robot
   vtheta_samples: 20
   dwa: true
   simple_attractor: false
"""


def namespace(text: str, name: str) -> dict[str, Any]:
    """The planner's namespace with move_base's controller_frequency, as the planner's
    upward search finds it."""
    loaded = yaml.safe_load(text)
    return {**loaded[name], "controller_frequency": loaded["controller_frequency"]}


def test_the_course_parameters() -> None:
    planner = make_local_planner(
        "base_local_planner/TrajectoryPlannerROS", namespace(COURSE_YAML, "TrajectoryPlannerROS")
    )
    assert isinstance(planner, TrajectoryPlannerROS)
    p = planner.params
    assert p.sim_period == pytest.approx(1 / 3)
    assert (p.max_vel_x, p.min_vel_x) == (0.5, 0.1)
    assert (p.max_vel_theta, p.min_vel_theta, p.min_in_place_vel_theta) == (1.0, -1.0, 0.5)
    assert (p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta) == (1.5, 0.0, 1.2)
    assert not p.holonomic_robot
    assert (p.path_distance_bias, p.goal_distance_bias, p.occdist_scale) == (0.9, 0.6, 0.1)
    assert (p.meter_scoring, p.prune_plan, p.dwa, p.simple_attractor) == (True, True, True, False)
    assert (p.vx_samples, p.vtheta_samples) == (8, 20)
    assert (p.xy_goal_tolerance, p.yaw_goal_tolerance) == (0.1, 0.1)
    assert p.escape_vel == -0.1


def test_rbx1_parameters_with_their_old_names() -> None:
    p = TrajectoryPlannerParams.from_mapping(namespace(RBX1_YAML, "TrajectoryPlannerROS"))
    # max_rotational_vel sets both rotation limits; acc_lim_th is acc_lim_theta
    assert (p.max_vel_theta, p.min_vel_theta) == (1.0, -1.0)
    assert p.acc_lim_theta == 1.2
    assert (p.path_distance_bias, p.goal_distance_bias) == (0.4, 0.8)
    assert (p.sim_granularity, p.angular_sim_granularity) == (0.05, 0.1)
    assert p.xy_goal_tolerance == 0.05


def test_trajectory_planner_defaults() -> None:
    p = TrajectoryPlannerParams.from_mapping({})
    assert p.sim_period == 0.05  # no controller_frequency: 20 Hz
    assert p.y_vels == (-0.3, -0.1, 0.1, 0.3)
    assert p.angular_sim_granularity == p.sim_granularity == 0.025
    assert (p.holonomic_robot, p.dwa, p.prune_plan) == (True, True, True)
    assert p.escape_reset_theta == pytest.approx(math.pi / 4)
    assert (
        TrajectoryPlannerParams.from_mapping({"sim_granularity": 0.1}).angular_sim_granularity
        == 0.1
    )


def test_new_names_win_over_old_ones() -> None:
    p = TrajectoryPlannerParams.from_mapping(
        {"path_distance_bias": 0.7, "pdist_scale": 0.2, "escape_vel": -0.2, "backup_vel": -0.3}
    )
    assert (p.path_distance_bias, p.escape_vel) == (0.7, -0.2)
    d = DWAPlannerParams.from_mapping(
        {"max_trans_vel": 0.3, "min_rot_vel": 0.2, "max_rot_vel": 0.8, "max_vel_trans": 0.4}
    )
    assert (d.max_vel_trans, d.min_vel_theta, d.max_vel_theta) == (0.4, 0.2, 0.8)


def test_y_vels_as_a_string_or_a_list() -> None:
    assert TrajectoryPlannerParams.from_mapping({"y_vels": "[-0.2, 0.2]"}).y_vels == (-0.2, 0.2)
    assert TrajectoryPlannerParams.from_mapping({"y_vels": [-0.2, 0.2]}).y_vels == (-0.2, 0.2)
    with pytest.raises(ValueError, match=r"parameter y_vels: expected a list of numbers"):
        TrajectoryPlannerParams.from_mapping({"y_vels": "[-0.2, fast]"})


def test_dwa_defaults_and_samples() -> None:
    planner = make_local_planner("dwa_local_planner/DWAPlannerROS", {"controller_frequency": 10})
    assert isinstance(planner, DWAPlannerROS)
    p = planner.params
    assert p.sim_period == pytest.approx(0.1)
    assert (p.sim_time, p.sim_granularity, p.angular_sim_granularity) == (1.7, 0.025, 0.1)
    assert (p.path_distance_bias, p.goal_distance_bias, p.occdist_scale) == (32.0, 24.0, 0.01)
    assert (p.vx_samples, p.vy_samples, p.vth_samples) == (3, 10, 20)
    assert (p.prune_plan, p.use_dwa) == (False, True)
    # no samples in a dimension means one, as ROS corrects it
    assert DWAPlannerParams.from_mapping({"vy_samples": 0}).vy_samples == 1


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"max_vel_x": "fast"}, r"parameter max_vel_x: expected a number, got 'fast'"),
        ({"vx_samples": 2.5}, r"parameter vx_samples: expected a whole number, got 2\.5"),
        ({"prune_plan": "yes"}, r"parameter prune_plan: expected true or false, got 'yes'"),
        ({"sim_time": 0}, r"parameter sim_time must be positive, got 0"),
        ({"max_vel_x": 0.1, "min_vel_x": 0.2}, r"max_vel_x \(0\.1\) and min_vel_x \(0\.2\)"),
    ],
)
def test_bad_values_name_the_parameter(values: dict[str, Any], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        make_local_planner("base_local_planner/TrajectoryPlannerROS", values)
    with pytest.raises(ValueError, match=message):
        make_local_planner("dwa_local_planner/DWAPlannerROS", values)


def test_an_unknown_plugin_names_the_supported_ones() -> None:
    with pytest.raises(UnknownPluginError) as caught:
        make_local_planner("teb_local_planner/TebLocalPlannerROS", {})
    assert str(caught.value) == (
        "unknown local planner plugin 'teb_local_planner/TebLocalPlannerROS' (supported: "
        "base_local_planner/TrajectoryPlannerROS, dwa_local_planner/DWAPlannerROS)"
    )
    assert isinstance(caught.value, ValueError)
    assert caught.value.kind == "local planner"
    assert caught.value.supported == LOCAL_PLANNERS


@pytest.mark.parametrize("cls", [TrajectoryPlannerParams, DWAPlannerParams])
def test_every_field_is_read_under_its_own_name(cls: Any) -> None:
    """Each parameter set to a value of its kind other than its default comes back."""
    import dataclasses

    derived = {"sim_period"}  # worked out from controller_frequency
    values: dict[str, Any] = {}
    for i, field in enumerate(dataclasses.fields(cls)):
        default = field.default
        if field.name in derived:
            continue
        if isinstance(default, bool):
            values[field.name] = not default
        elif isinstance(default, int):
            values[field.name] = default + 7
        elif isinstance(default, float):
            values[field.name] = 100.0 - i  # positive; a max_* (listed first) above its min_*
        else:
            values[field.name] = [0.5, -0.5]
    params = cls.from_mapping(values)
    for name, value in values.items():
        got = getattr(params, name)
        assert got == (tuple(value) if isinstance(value, list) else value), name
    assert params.sim_period == pytest.approx(1.0 / values["controller_frequency"])
