"""The local planners drive a kinematic robot (simulated time) along global plans on
hand-made cost grids, as move_base runs them."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from belvedere.nav.costmap import INSCRIBED, LETHAL
from belvedere.nav.local import (
    DWAPlannerROS,
    LocalPlanner,
    NoTrajectoryError,
    TrajectoryPlannerROS,
    make_local_planner,
)
from belvedere.nav.local._maps import FootprintModel
from tests.nav.local_world import (
    SQUARE,
    Run,
    cell_cost,
    corridor,
    drive,
    inflate,
    l_corridor,
    polyline,
    walled,
)

TP = "base_local_planner/TrajectoryPlannerROS"
DWA = "dwa_local_planner/DWAPlannerROS"

# the course's mbot_navigation TrajectoryPlannerROS settings (controller_frequency 3 Hz)
COURSE_TP: dict[str, Any] = {
    "controller_frequency": 3.0,
    "max_vel_x": 0.5,
    "min_vel_x": 0.1,
    "max_vel_theta": 1.0,
    "min_vel_theta": -1.0,
    "min_in_place_vel_theta": 0.5,
    "escape_vel": -0.1,
    "acc_lim_x": 1.5,
    "acc_lim_y": 0.0,
    "acc_lim_theta": 1.2,
    "holonomic_robot": False,
    "yaw_goal_tolerance": 0.1,
    "xy_goal_tolerance": 0.1,
    "pdist_scale": 0.9,
    "gdist_scale": 0.6,
    "meter_scoring": True,
    "occdist_scale": 0.1,
    "sim_time": 1.0,
    "sim_granularity": 0.025,
    "angular_sim_granularity": 0.025,
    "vx_samples": 8,
    "vtheta_samples": 20,
}

CASES = [
    pytest.param(TP, {"controller_frequency": 10.0, "holonomic_robot": False}, id="tp-diff"),
    pytest.param(TP, {"controller_frequency": 5.0, "holonomic_robot": True}, id="tp-holonomic"),
    pytest.param(TP, {"controller_frequency": 10.0, "dwa": False}, id="tp-rollout"),
    pytest.param(TP, COURSE_TP, id="tp-course"),
    pytest.param(TP, {"controller_frequency": 10.0, "heading_scoring": True}, id="tp-heading"),
    pytest.param(TP, {"controller_frequency": 10.0, "simple_attractor": True}, id="tp-attractor"),
    pytest.param(
        DWA, {"controller_frequency": 10.0, "max_vel_y": 0.0, "min_vel_y": 0.0}, id="dwa-diff"
    ),
    pytest.param(DWA, {"controller_frequency": 5.0, "vx_samples": 6}, id="dwa-holonomic"),
    pytest.param(
        DWA,
        {"controller_frequency": 10.0, "use_dwa": False, "max_vel_y": 0.0, "min_vel_y": 0.0},
        id="dwa-no-window",
    ),
]


def assert_arrived(planner: LocalPlanner, run: Run, goal: tuple[float, float, float]) -> None:
    params = planner.params
    assert run.reached, f"not at the goal after {len(run.poses)} cycles: {run.pose}"
    x, y, yaw = run.pose
    assert math.hypot(x - goal[0], y - goal[1]) <= params.xy_goal_tolerance
    assert abs(math.remainder(yaw - goal[2], math.tau)) <= params.yaw_goal_tolerance


def assert_clear(run: Run, grid_costs: Any) -> None:
    """The robot's centre never entered an inscribed or lethal cell, and its footprint never
    touched a lethal one."""
    model = FootprintModel(SQUARE, grid_costs.resolution)
    poses = np.array(run.poses)
    for x, y, _ in poses:
        assert cell_cost(grid_costs, x, y) < INSCRIBED
    _, valid = model.cost(grid_costs, poses[:, 0], poses[:, 1], poses[:, 2])
    assert valid.all()


@pytest.mark.parametrize(("plugin", "params"), CASES)
def test_follows_a_straight_plan(plugin: str, params: dict[str, Any]) -> None:
    grid = corridor()
    plan = polyline((0.8, 1.0), (5.0, 1.0), goal_yaw=0.0)
    planner = make_local_planner(plugin, params)
    run = drive(planner, grid, plan, (0.8, 1.0, 0.0))
    assert_arrived(planner, run, (5.0, 1.0, 0.0))
    assert_clear(run, grid)
    # it drove forward along the corridor, not backwards or across it
    xs = np.array(run.poses)[:, 0]
    assert np.all(np.diff(xs) > -0.02)
    assert max(abs(p[1] - 1.0) for p in run.poses) < 0.2


@pytest.mark.parametrize(("plugin", "params"), CASES)
def test_follows_an_l_shaped_plan(plugin: str, params: dict[str, Any]) -> None:
    grid = l_corridor()
    plan = polyline((0.8, 0.8), (2.8, 0.8), (2.8, 3.2), goal_yaw=math.pi / 2)
    planner = make_local_planner(plugin, params)
    run = drive(planner, grid, plan, (0.8, 0.8, 0.0))
    assert_arrived(planner, run, (2.8, 3.2, math.pi / 2))
    assert_clear(run, grid)
    # the local plans run from the robot in the grid's frame
    moving = [c for c in run.commands if len(c.local_plan)]
    assert moving
    for pose, command in zip(run.poses, run.commands, strict=False):
        if len(command.local_plan):
            assert np.allclose(command.local_plan[0], pose)


@pytest.mark.parametrize("plugin", [TP, DWA])
def test_a_blocked_path_has_no_trajectory(plugin: str) -> None:
    lethal = walled(6.0, 2.0)
    lethal[:, 60] = True  # a wall across the corridor at x = 3 m
    grid = inflate(lethal)
    planner = make_local_planner(plugin, {"controller_frequency": 10.0})
    planner.set_plan(polyline((0.8, 1.0), (5.0, 1.0), goal_yaw=0.0))
    with pytest.raises(NoTrajectoryError, match=r"no valid trajectory"):
        planner.compute(grid, (0.8, 1.0, 0.0), (0.0, 0.0, 0.0), SQUARE)


@pytest.mark.parametrize("plugin", [TP, DWA])
def test_no_plan_is_no_trajectory(plugin: str) -> None:
    planner = make_local_planner(plugin, {})
    with pytest.raises(NoTrajectoryError, match=r"no plan"):
        planner.compute(corridor(), (0.8, 1.0, 0.0), (0.0, 0.0, 0.0), SQUARE)
    planner.set_plan(polyline((50.0, 50.0), (51.0, 50.0), goal_yaw=0.0))
    with pytest.raises(NoTrajectoryError, match=r"no pose of the plan lies in the local"):
        planner.compute(corridor(), (0.8, 1.0, 0.0), (0.0, 0.0, 0.0), SQUARE)


@pytest.mark.parametrize(
    ("plugin", "params"),
    [
        (
            TP,
            {"controller_frequency": 10.0, "holonomic_robot": False, "min_in_place_vel_theta": 0.3},
        ),
        (DWA, {"controller_frequency": 10.0}),
        (DWA, {"controller_frequency": 5.0, "max_vel_y": 0.0, "min_vel_y": 0.0, "vx_samples": 6}),
    ],
)
def test_acceleration_limits_hold_between_cycles(plugin: str, params: dict[str, Any]) -> None:
    grid = l_corridor()
    plan = polyline((0.8, 0.8), (2.8, 0.8), (2.8, 3.2), goal_yaw=math.pi / 2)
    planner = make_local_planner(plugin, params)
    run = drive(planner, grid, plan, (0.8, 0.8, 0.0))
    assert run.reached
    p = planner.params
    period = p.sim_period
    limits = np.array([p.acc_lim_x, p.acc_lim_y, p.acc_lim_theta]) * period + 1e-9
    checked = 0
    for pose, velocity, command in zip(run.poses, run.velocities, run.commands, strict=False):
        if math.hypot(pose[0] - 2.8, pose[1] - 3.2) <= p.xy_goal_tolerance:
            break  # stopping and turning at the goal follow their own rules
        change = np.abs(np.array([command.vx, command.vy, command.vth]) - velocity)
        assert np.all(change <= limits), (pose, velocity, command)
        checked += 1
    assert checked > 20


def test_a_differential_robot_never_strafes() -> None:
    grid = l_corridor()
    plan = polyline((0.8, 0.8), (2.8, 0.8), (2.8, 3.2), goal_yaw=math.pi / 2)
    for plugin, params in [
        (TP, {"holonomic_robot": False, "controller_frequency": 10.0}),
        (DWA, {"max_vel_y": 0.0, "min_vel_y": 0.0, "controller_frequency": 10.0}),
    ]:
        run = drive(make_local_planner(plugin, params), grid, plan, (0.8, 0.8, 0.0))
        assert run.reached
        assert all(c.vy == 0.0 for c in run.commands)


def test_a_holonomic_robot_strafes_towards_a_plan_beside_it() -> None:
    # the plan runs sideways (+y) from a robot facing +x; the DWA may sample vy
    grid = inflate(walled(3.0, 3.0))
    plan = polyline((1.5, 1.0), (1.5, 2.0), goal_yaw=0.0)
    holonomic = drive(
        make_local_planner(DWA, {"controller_frequency": 10.0, "yaw_goal_tolerance": 0.2}),
        grid,
        plan,
        (1.5, 1.0, 0.0),
    )
    assert holonomic.reached
    assert any(c.vy > 0.0 for c in holonomic.commands)
    differential = drive(
        make_local_planner(DWA, {"controller_frequency": 10.0, "max_vel_y": 0.0, "min_vel_y": 0.0}),
        grid,
        plan,
        (1.5, 1.0, 0.0),
    )
    assert differential.reached
    assert all(c.vy == 0.0 for c in differential.commands)
    # the differential robot had to turn towards the plan; the holonomic one needed less
    turned = [abs(p[2]) for p in differential.poses]
    assert max(turned) > 1.0


@pytest.mark.parametrize("plugin", [TP, DWA])
def test_turns_to_the_goal_yaw_in_place(plugin: str) -> None:
    grid = corridor()
    planner = make_local_planner(plugin, {"controller_frequency": 10.0})
    plan = polyline((1.0, 1.0), (3.0, 1.0), goal_yaw=math.pi / 2)
    # already within xy_goal_tolerance of the goal, facing along the corridor
    run = drive(planner, grid, plan, (2.95, 1.0, 0.0))
    assert_arrived(planner, run, (3.0, 1.0, math.pi / 2))
    moving = run.commands[:-1]
    assert all(c.vx == 0.0 and c.vy == 0.0 for c in run.commands)
    assert all(c.vth > 0.0 for c in moving)  # the shorter way round
    assert run.commands[-1].vth == 0.0
    assert all(len(c.local_plan) == 0 for c in run.commands)


@pytest.mark.parametrize("plugin", [TP, DWA])
@pytest.mark.parametrize("latch", [True, False])
def test_latch_xy_goal_tolerance(plugin: str, latch: bool) -> None:
    grid = corridor()
    planner = make_local_planner(
        plugin, {"controller_frequency": 10.0, "latch_xy_goal_tolerance": latch}
    )
    planner.set_plan(polyline((1.0, 1.0), (3.0, 1.0), goal_yaw=math.pi / 2))
    inside = planner.compute(grid, (2.95, 1.0, 0.0), (0.0, 0.0, 0.0), SQUARE)
    assert (inside.vx, inside.vy) == (0.0, 0.0)
    assert inside.vth > 0.0
    # the robot drifted out of the tolerance while turning
    drifted = planner.compute(grid, (2.8, 1.0, 0.6), (0.0, 0.0, inside.vth), SQUARE)
    if latch:
        assert (drifted.vx, drifted.vy) == (0.0, 0.0)
        assert drifted.vth > 0.0
        assert len(drifted.local_plan) == 0
    else:
        assert len(drifted.local_plan) > 0  # back to following the plan
    if latch:
        # a new plan clears the latch
        planner.set_plan(polyline((1.0, 1.0), (3.0, 1.0), goal_yaw=math.pi / 2))
        again = planner.compute(grid, (2.8, 1.0, 0.6), (0.0, 0.0, 0.0), SQUARE)
        assert len(again.local_plan) > 0


def test_trajectory_planner_reports_the_goal_from_its_last_cycle() -> None:
    planner = TrajectoryPlannerROS({"controller_frequency": 10.0})
    planner.set_plan(polyline((1.0, 1.0), (3.0, 1.0), goal_yaw=0.0))
    at_goal = (3.0, 1.0, 0.0)
    assert not planner.goal_reached(at_goal, (0.0, 0.0, 0.0))
    command = planner.compute(corridor(), at_goal, (0.0, 0.0, 0.0), SQUARE)
    assert (command.vx, command.vy, command.vth) == (0.0, 0.0, 0.0)
    assert planner.goal_reached(at_goal, (0.0, 0.0, 0.0))


def test_dwa_goal_needs_the_robot_stopped() -> None:
    planner = DWAPlannerROS({"controller_frequency": 10.0})
    planner.set_plan(polyline((1.0, 1.0), (3.0, 1.0), goal_yaw=0.0))
    assert not planner.goal_reached((3.0, 1.0, 0.0), (0.3, 0.0, 0.0))
    assert planner.goal_reached((3.0, 1.0, 0.0), (0.05, 0.0, 0.05))
    assert not planner.goal_reached((3.0, 1.0, 0.5), (0.0, 0.0, 0.0))


def test_stops_under_the_acceleration_limits_at_the_goal() -> None:
    planner = TrajectoryPlannerROS({"controller_frequency": 10.0, "acc_lim_x": 1.0})
    planner.set_plan(polyline((1.0, 1.0), (3.0, 1.0), goal_yaw=math.pi / 2))
    command = planner.compute(corridor(), (2.95, 1.0, 0.0), (0.4, 0.0, 0.0), SQUARE)
    assert command.vx == pytest.approx(0.3)  # 0.4 - 1.0 m/s² x 0.1 s
    assert command.vth == 0.0


def test_escapes_backwards_when_boxed_in() -> None:
    # a wall 2 cm ahead: no forward or turning trajectory is valid for the square robot,
    # but the path behind is free: TrajectoryPlannerROS backs up at escape_vel
    lethal = walled(6.0, 2.0)
    lethal[:, 26] = True  # x = 1.3 m
    grid = inflate(lethal)
    grid.costs[grid.costs == INSCRIBED] = 100  # keep the centre's cell usable
    planner = make_local_planner(TP, {"controller_frequency": 10.0, "holonomic_robot": False})
    planner.set_plan(polyline((1.13, 1.0), (0.5, 1.0), goal_yaw=0.0))
    command = planner.compute(grid, (1.13, 1.0, 0.0), (0.0, 0.0, 0.0), SQUARE)
    assert (command.vx, command.vy, command.vth) == (-0.1, 0.0, 0.0)


def test_unknown_cells_block_the_footprint() -> None:
    grid = corridor()
    grid.costs[:, 50:] = 255
    model = FootprintModel(SQUARE, grid.resolution)
    _, valid = model.cost(grid, np.array([2.0, 2.3, 2.4]), np.array([1.0, 1.0, 1.0]), np.zeros(3))
    assert valid.tolist() == [True, True, False]
    grid.costs[:, 50:] = 0
    grid.costs[20, 50] = LETHAL
    _, valid = model.cost(grid, np.array([2.3, 2.38]), np.array([1.0, 1.0]), np.zeros(2))
    assert valid.tolist() == [True, False]


def test_dwa_bars_reversing_a_rotation_in_place_until_the_robot_turned() -> None:
    from belvedere.nav.local._dwa import _Oscillation

    flags = _Oscillation()
    samples = np.array([[0.0, 0.0, 0.5], [0.0, 0.0, -0.5], [0.3, 0.0, 0.5]])
    flags.update((1.0, 1.0, 0.0), (0.0, 0.0, 0.5), 0.1, 0.05, 0.2)
    assert not flags.barred(samples).any()
    flags.update((1.0, 1.0, 0.05), (0.0, 0.0, -0.5), 0.1, 0.05, 0.2)
    # turning back the other way again is barred, whatever the forward speed
    assert flags.barred(samples).tolist() == [True, False, True]
    flags.update((1.0, 1.0, 0.1), (0.0, 0.0, -0.5), 0.1, 0.05, 0.2)
    assert flags.barred(samples).tolist() == [True, False, True]
    flags.update((1.0, 1.0, 0.3), (0.0, 0.0, -0.5), 0.1, 0.05, 0.2)
    assert not flags.barred(samples).any()  # turned 0.25 rad from where it was flagged


def test_a_cornered_holonomic_robot_strafes_and_a_differential_one_backs_up() -> None:
    # walls 2 cm beyond the square's front and left edges: driving forward or turning in
    # place would touch them; the plan leads away to the right
    lethal = walled(3.0, 3.0)
    lethal[34, 20:35] = True  # y = 1.70 m
    lethal[20:35, 34] = True  # x = 1.70 m
    grid = inflate(lethal)
    plan = polyline((1.49, 1.52), (1.49, 0.5), goal_yaw=0.0)
    commands = []
    for holonomic in (True, False):
        planner = make_local_planner(
            TP, {"controller_frequency": 10.0, "holonomic_robot": holonomic}
        )
        planner.set_plan(plan)
        command = planner.compute(grid, (1.49, 1.52, 0.0), (0.0, 0.0, 0.0), SQUARE)
        commands.append((command.vx, command.vy, command.vth))
    # the holonomic robot tries y_vels and takes a strafe to the right; the other escapes
    assert commands == [(0.0, -0.3, 0.0), (-0.1, 0.0, 0.0)]
