"""move_base on the fake TurtleBot (rbx1's fake_move_base_blank_map.launch beside the ArbotiX
fake base): goals on its action and on move_base_simple/goal are reached within the local
planner's tolerances, make_plan answers, an unreachable goal is aborted after the recoveries,
and an unknown planner plugin is one error at its YAML line."""

from __future__ import annotations

import itertools
import logging
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.graph import ActionClient, GoalStatus, Graph
from belvedere.launch import LaunchError, load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from tests.conftest import EXAMPLES


def _launch(tmp_path: Path, extra: str = "") -> Path:
    launch = tmp_path / "fake_nav.launch"
    launch.write_text(
        "<launch>\n"
        f'  <include file="{EXAMPLES}/rbx1_bringup/launch/fake_turtlebot.launch"/>\n'
        f'  <include file="{EXAMPLES}/rbx1_nav/launch/fake_move_base_blank_map.launch"/>\n'
        f"{extra}</launch>\n"
    )
    return launch


def _start(launch: Path) -> Graph:
    packages = PackageIndex.from_environment(near=EXAMPLES / "rbx1_nav/package.xml")
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    return graph


def _goal(x: float, y: float, yaw: float) -> dict[str, Any]:
    orientation = {"z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}
    pose = {"position": {"x": x, "y": y}, "orientation": orientation}
    return {"target_pose": {"header": {"frame_id": "map"}, "pose": pose}}


def _yaw(q: Any) -> float:
    return 2 * math.atan2(q.z, q.w)


@pytest.fixture
def fake_nav(tmp_path: Path) -> Any:
    graph = _start(_launch(tmp_path))
    probe = graph.create_node("probe")
    odom: list[Any] = []
    probe.subscribe("/odom", "nav_msgs/Odometry", lambda m: odom.append(m.pose.pose))
    yield graph, probe, odom
    graph.shutdown()


def test_goals_on_the_action_are_reached(fake_nav: Any) -> None:
    graph, probe, odom = fake_nav
    client = ActionClient(probe, "/move_base", "move_base_msgs/MoveBase")
    plans: list[Any] = []
    probe.subscribe("/move_base/NavfnROS/plan", "nav_msgs/Path", plans.append)
    graph.run(duration=1.0)
    for x, y, yaw in [(2.0, 1.0, 1.0), (-1.5, 2.0, math.pi), (0.0, -2.0, -1.5)]:
        goal = client.send_goal(_goal(x, y, yaw))
        graph.run(duration=60.0, until=lambda goal=goal: client.done(goal))
        assert client.status[goal] == GoalStatus.SUCCEEDED
        graph.run(duration=0.5)
        here = odom[-1]
        # the stand-in's tolerances: 7.5 cm, 0.1 rad (and what the robot coasts after the stop)
        assert math.hypot(here.position.x - x, here.position.y - y) < 0.09
        assert abs(math.remainder(_yaw(here.orientation) - yaw, math.tau)) < 0.15
        assert client.feedback[goal]  # the robot's position on the way
    assert plans
    assert plans[-1].header.frame_id == "map"


def test_short_goals_on_cell_corners_end(fake_nav: Any, caplog: pytest.LogCaptureFixture) -> None:
    """The rospy goal sequence that once stalled at wall time: goals on cell corners, the last
    a short 90 degree one. With a tolerance under a cell's diagonal the robot stopped in the
    goal's cell 5.01 cm from (0.8, 0.8) and turned in place for good."""
    graph, probe, odom = fake_nav
    client = ActionClient(probe, "/move_base", "move_base_msgs/MoveBase")
    graph.run(duration=1.0)
    sequence = [(0.8, 0.0, 0.0), (0.8, 0.8, 1.57), (0.0, 0.0, 0.0), (0.8, 0.8, 1.57)]
    with caplog.at_level(logging.WARNING, logger="belvedere"):
        for x, y, yaw in sequence:
            goal = client.send_goal(_goal(x, y, yaw))
            graph.run(duration=60.0, until=lambda goal=goal: client.done(goal))
            assert client.status[goal] == GoalStatus.SUCCEEDED, (x, y, yaw)
            here = odom[-1]
            assert math.hypot(here.position.x - x, here.position.y - y) < 0.09
    assert "xy_goal_tolerance" not in caplog.text


def test_a_goal_tolerance_under_a_cell_is_warned(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    params = tmp_path / "tolerance.yaml"
    params.write_text("TrajectoryPlannerROS: {xy_goal_tolerance: 0.05}\n")
    graph = _start(
        _launch(tmp_path, f'  <rosparam ns="move_base" file="{params}" command="load"/>\n')
    )
    try:
        client = ActionClient(graph.create_node("probe"), "/move_base", "move_base_msgs/MoveBase")
        graph.run(duration=1.0)
        with caplog.at_level(logging.WARNING, logger="belvedere"):
            goal = client.send_goal(_goal(0.5, 0.0, 0.0))
            graph.run(duration=30.0, until=lambda: client.done(goal))
    finally:
        graph.shutdown()
    assert (
        "TrajectoryPlannerROS/xy_goal_tolerance 0.05 m is less than a local costmap cell's "
        "diagonal (0.071 m at 0.05 m/cell)"
    ) in caplog.text


def test_a_simple_goal_is_reached(fake_nav: Any) -> None:
    graph, probe, odom = fake_nav
    goals = probe.publisher("/move_base_simple/goal", "geometry_msgs/PoseStamped")
    current: list[Any] = []
    probe.subscribe("/move_base/current_goal", "geometry_msgs/PoseStamped", current.append)
    graph.run(duration=1.0)
    goals.publish_data(
        {"header": {"frame_id": "map"}, "pose": _goal(1.5, 0.0, 0.0)["target_pose"]["pose"]}
    )
    graph.run(
        duration=40.0,
        until=lambda: (
            bool(odom) and math.hypot(odom[-1].position.x - 1.5, odom[-1].position.y) < 0.075
        ),
    )
    assert current
    assert current[-1].pose.position.x == pytest.approx(1.5)
    assert math.hypot(odom[-1].position.x - 1.5, odom[-1].position.y) < 0.075


def test_make_plan_and_an_unreachable_goal(fake_nav: Any) -> None:
    graph, probe, _ = fake_nav
    graph.run(duration=1.0)
    request = {
        "start": {"header": {"frame_id": "map"}, "pose": {"orientation": {"w": 1.0}}},
        "goal": {
            "header": {"frame_id": "map"},
            "pose": {"position": {"x": 3.0, "y": 3.0}, "orientation": {"w": 1.0}},
        },
        "tolerance": 0.0,
    }
    response = probe.call_service("/move_base/make_plan", "nav_msgs/GetPlan", request)
    poses = response.plan.poses
    assert len(poses) > 10
    first, last = poses[0].pose.position, poses[-1].pose.position
    assert math.hypot(first.x, first.y) < 0.1
    assert math.hypot(last.x - 3.0, last.y - 3.0) < 0.1
    length = sum(
        math.hypot(b.pose.position.x - a.pose.position.x, b.pose.position.y - a.pose.position.y)
        for a, b in itertools.pairwise(poses)
    )
    assert length < math.hypot(3.0, 3.0) * 1.1  # nearly straight on a blank map
    probe.call_service("/move_base/clear_costmaps", "std_srvs/Empty")
    # outside the map (the blank map is 10 m x 10 m about the origin): no plan, ever
    client = ActionClient(probe, "/move_base", "move_base_msgs/MoveBase")
    goal = client.send_goal(_goal(20.0, 0.0, 0.0))
    graph.run(duration=120.0, until=lambda: client.done(goal))
    assert client.status[goal] == GoalStatus.ABORTED


def test_an_unknown_planner_is_one_error_at_its_yaml_line(tmp_path: Path) -> None:
    params = tmp_path / "planners.yaml"
    params.write_text(
        "controller_frequency: 3.0\nbase_local_planner: teb_local_planner/TebLocalPlannerROS\n"
    )
    extra = f'  <rosparam ns="move_base" file="{params}" command="load"/>\n'
    with pytest.raises(LaunchError) as caught:
        _start(_launch(tmp_path, extra))
    text = str(caught.value)
    assert text.startswith(f"{params}:2:21: error: /move_base: parameter base_local_planner: ")
    assert "unknown local planner plugin 'teb_local_planner/TebLocalPlannerROS'" in text
    assert "base_local_planner/TrajectoryPlannerROS, dwa_local_planner/DWAPlannerROS" in text


def _recovering(tmp_path: Path, yaml_text: str) -> Graph:
    params = tmp_path / "recoveries.yaml"
    params.write_text(
        "recovery_behavior_enabled: true\nclearing_rotation_allowed: false\n" + yaml_text
    )
    return _start(
        _launch(tmp_path, f'  <rosparam ns="move_base" file="{params}" command="load"/>\n')
    )


@pytest.mark.parametrize(
    ("layers", "warned"),
    [
        ("", True),  # the default ["obstacles"]: the pre-Hydro costmaps have "obstacle_layer"
        (
            "conservative_reset: {layer_names: [obstacle_layer]}\n"
            "aggressive_reset: {layer_names: [obstacle_layer]}\n",
            False,
        ),
    ],
)
def test_clearing_recoveries_clear_the_layers_they_name(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, layers: str, warned: bool
) -> None:
    graph = _recovering(tmp_path, layers)
    try:
        probe = graph.create_node("probe")
        client = ActionClient(probe, "/move_base", "move_base_msgs/MoveBase")
        graph.run(duration=1.0)
        with caplog.at_level(logging.INFO, logger="belvedere"):
            goal = client.send_goal(_goal(20.0, 0.0, 0.0))  # off the map: no plan, ever
            graph.run(duration=60.0, until=lambda: client.done(goal))
    finally:
        graph.shutdown()
    assert client.status[goal] == GoalStatus.ABORTED
    assert "recovery: conservative_reset" in caplog.text
    assert "recovery: aggressive_reset" in caplog.text
    missing = "cannot clear layer obstacles: it does not exist"
    assert (missing in caplog.text) is warned
    if warned:
        assert "/move_base/global_costmap: " + missing in caplog.text
        assert "/move_base/local_costmap: " + missing in caplog.text


def test_a_bad_clearing_parameter_is_one_error(tmp_path: Path) -> None:
    with pytest.raises(LaunchError, match=r"conservative_reset/affected_maps must be 'local', "):
        _recovering(tmp_path, "conservative_reset: {affected_maps: none}\n")
    with pytest.raises(LaunchError, match=r"aggressive_reset/layer_names must be a list"):
        _recovering(tmp_path, "aggressive_reset: {layer_names: obstacles}\n")


def test_oscillation_runs_the_recoveries_in_turn_then_aborts(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    # the robot cannot cover oscillation_distance within oscillation_timeout: it oscillates
    graph = _recovering(tmp_path, "oscillation_timeout: 2.0\noscillation_distance: 5.0\n")
    try:
        client = ActionClient(graph.create_node("probe"), "/move_base", "move_base_msgs/MoveBase")
        graph.run(duration=1.0)
        with caplog.at_level(logging.INFO, logger="belvedere"):
            goal = client.send_goal(_goal(3.0, 0.0, 0.0))
            graph.run(duration=30.0, until=lambda: client.done(goal))
    finally:
        graph.shutdown()
    assert client.status[goal] == GoalStatus.ABORTED
    recoveries = [line for line in caplog.text.splitlines() if "; recovery: " in line]
    assert len(recoveries) == 2
    assert "the robot is oscillating; recovery: conservative_reset" in recoveries[0]
    assert "the robot is oscillating; recovery: aggressive_reset" in recoveries[1]


CUSTOM_RECOVERIES = """\
recovery_behaviors:
  - {name: conservative_reset, type: clear_costmap_recovery/ClearCostmapRecovery}
  - {name: spin, type: rotate_recovery/RotateRecovery}
  - name: last_reset
    type: ClearCostmapRecovery
conservative_reset: {layer_names: [obstacle_layer], reset_distance: 1.5}
spin: {frequency: 10.0}
"""


def test_a_custom_recovery_list_runs_in_its_order_with_its_own_parameters(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    # clearing_rotation_allowed is false: it only prunes move_base's default list
    graph = _recovering(tmp_path, CUSTOM_RECOVERIES)
    try:
        probe = graph.create_node("probe")
        yaws: list[float] = []
        probe.subscribe(
            "/odom", "nav_msgs/Odometry", lambda m: yaws.append(_yaw(m.pose.pose.orientation))
        )
        client = ActionClient(probe, "/move_base", "move_base_msgs/MoveBase")
        graph.run(duration=1.0)
        with caplog.at_level(logging.INFO, logger="belvedere"):
            goal = client.send_goal(_goal(20.0, 0.0, 0.0))  # off the map: no plan, ever
            graph.run(duration=120.0, until=lambda: client.done(goal))
    finally:
        graph.shutdown()
    assert client.status[goal] == GoalStatus.ABORTED
    recoveries = [
        line.split("; recovery: ")[1] for line in caplog.text.splitlines() if "; recovery: " in line
    ]
    assert recoveries == ["conservative_reset", "spin", "last_reset"]
    # the spin turned the robot once around: its heading went through every quadrant
    turned = np.unwrap(np.array(yaws))
    assert turned.max() - turned.min() > 1.9 * math.pi
    # conservative_reset names the pre-Hydro obstacle layer; last_reset keeps the default
    # ["obstacles"], which no layer here is called
    missing = [line for line in caplog.text.splitlines() if "cannot clear layer obstacles" in line]
    assert missing
    assert "cannot clear layer obstacle_layer" not in caplog.text


def test_a_recovery_of_an_unknown_type_is_one_error_at_its_yaml_line(tmp_path: Path) -> None:
    bad = CUSTOM_RECOVERIES.replace(
        "type: ClearCostmapRecovery", "type: move_slow_and_clear/MoveSlowAndClear"
    )
    with pytest.raises(LaunchError) as caught:
        _recovering(tmp_path, bad)
    text = str(caught.value)
    # the recoveries file has two lines of its own before the list (_recovering)
    assert text.startswith(f"{tmp_path / 'recoveries.yaml'}:7:11: error: /move_base: parameter ")
    assert "recovery_behaviors[2]: unknown recovery behavior type " in text
    assert "'move_slow_and_clear/MoveSlowAndClear'" in text
    assert (
        "(supported: clear_costmap_recovery/ClearCostmapRecovery, rotate_recovery/RotateRecovery)"
        in text
    )
    assert text.count("error:") == 1


@pytest.mark.parametrize(
    ("yaml_text", "where", "expected"),
    [
        ("recovery_behaviors: spin\n", ":3:21:", r"recovery_behaviors must be a list of"),
        (
            "recovery_behaviors:\n  - {name: a, type: rotate_recovery/RotateRecovery}\n"
            "  - {name: a, type: rotate_recovery/RotateRecovery}\n",
            ":5:12:",
            r"recovery_behaviors\[1\]: the name 'a' is used twice",
        ),
        (
            "recovery_behaviors:\n  - {name: a}\n",
            ":4:5:",
            r"recovery_behaviors\[0\] needs a type \(a string\), got None",
        ),
    ],
)
def test_a_malformed_recovery_list_is_one_error_at_its_line(
    tmp_path: Path, yaml_text: str, where: str, expected: str
) -> None:
    with pytest.raises(LaunchError, match=rf"recoveries\.yaml{where} error: .*{expected}"):
        _recovering(tmp_path, yaml_text)
