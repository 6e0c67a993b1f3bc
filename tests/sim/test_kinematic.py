"""The fake ArbotiX driver: the base's integration, its quirks, servos and trajectories."""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import Any

import pytest

from belvedere.description.urdf import RobotModel
from belvedere.errors import BelvedereError, ParseError
from belvedere.graph import ActionClient, GoalStatus, Graph, Node, Publisher
from belvedere.msgs import types
from belvedere.sim.kinematic import (
    ArbotixConfig,
    ArbotixConfigError,
    ArbotixDriver,
    DiffControllerConfig,
    KinematicSimulation,
    default_config,
)
from belvedere.tf import TFBuffer, TransformListener
from belvedere.yamlfile import load_yaml, load_yaml_file
from tests.conftest import EXAMPLES

MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo_modern.xacro"
MBOT_YAML = EXAMPLES / "mbot_description/config/fake_mbot_arbotix.yaml"
RBX1_YAML = EXAMPLES / "rbx1_bringup/config/fake_turtlebot_arbotix.yaml"
TURTLEBOT = EXAMPLES / "rbx1_description/urdf/turtlebot.urdf.xacro"

ARM_YAML = """\
rate: 100
write_rate: 50
read_rate: 20
joints: {
  shoulder: {id: 1, max_speed: 90},
  elbow: {id: 2, max_speed: 180, invert: true},
  wrist: {id: 3, type: hobby_servo}
}
controllers: {
  arm_controller: {type: follow_controller, joints: [shoulder, elbow],
                   action_name: arm_controller/follow_joint_trajectory}
}
"""


def _collect(node: Node, topic: str, msg_type: str) -> list[Any]:
    got: list[Any] = []
    node.subscribe(topic, msg_type, got.append, queue_size=0)
    return got


def _drive(graph: Graph, node: Node, linear: float, angular: float, topic: str = "/cmd_vel") -> Any:
    pub = node.publisher(topic, "geometry_msgs/Twist", latch=True)
    pub.publish_data({"linear": {"x": linear}, "angular": {"z": angular}})
    return pub


def _circle_run() -> tuple[list[Any], list[Any]]:
    graph = Graph()
    config = ArbotixConfig.from_yaml(load_yaml_file(MBOT_YAML))
    KinematicSimulation(graph, RobotModel.from_path(MBOT), config)
    probe = graph.create_node("probe")
    odom = _collect(probe, "/odom", "nav_msgs/Odometry")
    tf = _collect(probe, "/tf", "tf2_msgs/TFMessage")
    _drive(graph, probe, 0.2, 0.5)
    graph.run(duration=10.0)
    return odom, tf


def test_circle_follows_the_originals_euler_integration() -> None:
    odom, tf = _circle_run()
    # 10 Hz from the course's YAML (rate defaults to 10), odom -> base_footprint.
    assert len(odom) == 100
    stamps = [m.header.stamp.sec + m.header.stamp.nanosec * 1e-9 for m in odom]
    assert stamps == pytest.approx([0.1 * (k + 1) for k in range(100)], abs=1e-9)
    assert {(m.header.frame_id, m.child_frame_id) for m in odom} == {("odom", "base_footprint")}
    # Explicit Euler, position before heading: vertex k is a sum of 0.02 m chords turning
    # 0.05 rad each (the original's exact arithmetic).
    x = y = th = 0.0
    for msg in odom:
        x, y, th = x + math.cos(th) * 0.02, y + math.sin(th) * 0.02, th + 0.05
        p = msg.pose.pose.position
        assert (p.x, p.y, p.z) == pytest.approx((x, y, 0.0), abs=1e-12)
        q = msg.pose.pose.orientation
        assert (q.x, q.y, q.z, q.w) == pytest.approx((0, 0, math.sin(th / 2), math.cos(th / 2)))
        assert (msg.twist.twist.linear.x, msg.twist.twist.angular.z) == (0.2, 0.5)
        assert not msg.pose.covariance.any()
    # The circle of radius 0.4 m around (0, 0.4): those vertices lie on a circle of radius
    # 0.40004 m centred half a step ahead, (0.01, 0.4), so they stay within 1.004 cm of it.
    radial = [
        abs(math.hypot(m.pose.pose.position.x, m.pose.pose.position.y - 0.4) - 0.4) for m in odom
    ]
    assert max(radial) < 0.0101
    # The heading is never wrapped: 10 s at 0.5 rad/s is 5 rad.
    assert th == pytest.approx(5.0)
    # The same pose goes out on /tf, odom -> base_footprint, at the same stamps.
    base_tf = [t for m in tf for t in m.transforms if t.child_frame_id == "base_footprint"]
    assert len(base_tf) == 100
    assert base_tf[-1].header.frame_id == "odom"
    assert base_tf[-1].transform.translation.x == odom[-1].pose.pose.position.x


def test_identical_second_run() -> None:
    first, _ = _circle_run()
    second, _ = _circle_run()
    serialize = types().serialize
    assert [serialize(m) for m in first] == [serialize(m) for m in second]


def test_last_command_persists_past_timeout_unless_cmd_vel_timeout() -> None:
    model = RobotModel.from_path(MBOT)
    for override, expected_x in ((None, 1.0), (0.5, 0.1)):
        graph = Graph()
        sim = KinematicSimulation(graph, model, cmd_vel_timeout=override)
        probe = graph.create_node("probe")
        pub = probe.publisher("/cmd_vel", "geometry_msgs/Twist")

        def command(p: Publisher = pub) -> None:
            p.publish_data({"linear": {"x": 0.2}})

        probe.timer(0.25, command, oneshot=True)
        graph.run(duration=5.25)
        base = sim.driver.base
        assert base is not None
        # Default: the original's timeout (1 s) never stops a fake base: 50 updates of
        # 0.02 m from 0.3 s to 5.2 s. With ours it stops at the first update more than
        # 0.5 s after the command (0.8 s): 5 updates.
        assert base.x == pytest.approx(expected_x, abs=1e-9)


def test_non_finite_commands_are_rejected_and_the_state_kept(
    caplog: pytest.LogCaptureFixture,
) -> None:
    graph = Graph()
    sim = KinematicSimulation(graph, RobotModel.from_path(MBOT))
    probe = graph.create_node("probe")
    pub = _drive(graph, probe, 0.1, 0.0)
    graph.run(duration=1.0)
    caplog.set_level(logging.WARNING, logger="belvedere.arbotix")
    # 1e308 m/s used to overflow the pose after 1.7 s; 351 m/s is just beyond the bound.
    for bad in (float("nan"), float("inf"), 1e308, 351.0):
        pub.publish_data({"linear": {"x": bad}})
        graph.run(duration=1.0)
    base = sim.driver.base
    assert base is not None
    assert base.dx == 0.1
    assert base.x == pytest.approx(0.5)
    assert [r.getMessage() for r in caplog.records if _arbotix_warning(r)] == [
        "/cmd_vel: ignored a command with linear.x=nan (not finite); keeping the last one"
    ]
    pub.publish_data({"linear": {"x": 0.2}, "angular": {"z": -350.0}})  # at the bounds: fine
    graph.run(duration=0.2)
    assert (base.dx, base.dr) == (0.2, -350.0)
    warnings = [r.getMessage() for r in caplog.records if _arbotix_warning(r)]
    assert warnings[-1] == "/cmd_vel: 4 commands were ignored"


def test_the_command_bounds_are_parameters(caplog: pytest.LogCaptureFixture) -> None:
    graph = Graph()
    graph.params.set("/belvedere/max_speed", 1.0)
    graph.params.set("/belvedere/max_turn_rate", 2.0)
    sim = KinematicSimulation(graph, RobotModel.from_path(MBOT))
    probe = graph.create_node("probe")
    caplog.set_level(logging.WARNING, logger="belvedere.arbotix")
    _drive(graph, probe, 0.5, 2.5)
    graph.run(duration=0.5)
    base = sim.driver.base
    assert base is not None
    assert (base.dx, base.dr) == (0.0, 0.0)
    assert [r.getMessage() for r in caplog.records if _arbotix_warning(r)] == [
        "/cmd_vel: ignored a command with angular.z=2.5 (beyond ±2 rad/s, "
        "/belvedere/max_turn_rate); keeping the last one"
    ]
    graph = Graph()
    graph.params.set("/belvedere/max_speed", -1)
    with pytest.raises(BelvedereError, match=r"/belvedere/max_speed must be a positive number"):
        KinematicSimulation(graph, RobotModel.from_path(MBOT))


def test_joint_states_and_diagnostics_as_the_original() -> None:
    graph = Graph()
    params = load_yaml(ARM_YAML + MBOT_YAML.read_text().replace("controllers: {", "x: {")).data
    params["controllers"]["base"] = {
        "type": "diff_controller",
        "ticks_meter": 1,
        "base_width": 0.3,
    }
    node = graph.create_node("arbotix", params=params)
    ArbotixDriver(node)
    probe = graph.create_node("probe")
    states = _collect(probe, "/joint_states", "sensor_msgs/JointState")
    diags = _collect(probe, "/diagnostics", "diagnostic_msgs/DiagnosticArray")
    graph.run(duration=1.0)
    assert len(states) == 20  # read_rate
    assert list(states[0].name) == [
        "shoulder",
        "elbow",
        "wrist",
        "base_l_wheel_joint",
        "base_r_wheel_joint",
    ]
    assert list(states[-1].position) == [0.0] * 5
    assert len(diags) == 1
    names = [s.name for s in diags[0].status]
    assert names == ["arm_controller", "base", "shoulder", "elbow", "wrist"]
    base_values = {v.key: v.value for v in diags[0].status[1].values}
    assert base_values == {"dX": "0.0", "dR": "0.0"}


def _arm(graph: Graph) -> tuple[ArbotixDriver, Node]:
    node = graph.create_node("arbotix", params=load_yaml(ARM_YAML).data)
    return ArbotixDriver(node), graph.create_node("probe")


def test_servo_moves_at_max_speed_and_clamps_to_its_ticks() -> None:
    graph = Graph()
    driver, probe = _arm(graph)
    cmd = probe.publisher("/shoulder/command", "std_msgs/Float64")
    cmd.publish_data({"data": 1.0})
    graph.run(duration=0.5)
    shoulder = driver.servos["shoulder"]
    # 90 deg/s stepped at write_rate 50 Hz: 25 steps of pi/100 in 0.5 s.
    assert shoulder.position == pytest.approx(25 * math.pi / 100)
    assert shoulder.velocity == pytest.approx(math.pi / 2)
    graph.run(duration=0.5)
    assert shoulder.position == pytest.approx(1.0)
    cmd.publish_data({"data": 10.0})  # beyond the 300-degree servo's reach
    graph.run(duration=5.0)
    assert shoulder.position == pytest.approx((1023 - 512) * math.radians(300) / 1024)
    cmd.publish_data({"data": float("nan")})
    graph.run(duration=0.5)
    assert math.isfinite(shoulder.position)


def test_follow_controller_executes_a_trajectory() -> None:
    graph = Graph()
    driver, probe = _arm(graph)
    client = ActionClient(
        probe, "/arm_controller/follow_joint_trajectory", "control_msgs/FollowJointTrajectory"
    )
    states = _collect(probe, "/joint_states", "sensor_msgs/JointState")
    goal = client.send_goal(
        {
            "trajectory": {
                "joint_names": ["elbow", "shoulder"],
                "points": [
                    {"positions": [0.5, 0.3], "time_from_start": [1, 0]},
                    {"positions": [-0.5, 0.6], "time_from_start": [2, 0]},
                ],
            }
        }
    )
    graph.run(duration=1.0)
    assert driver.servos["elbow"].position == pytest.approx(0.5, abs=1e-3)
    assert driver.servos["shoulder"].position == pytest.approx(0.3, abs=1e-3)
    assert client.status[goal] is GoalStatus.ACTIVE
    graph.run(duration=1.5)
    assert client.status[goal] is GoalStatus.SUCCEEDED
    assert client.results[goal].result.error_code == 0
    assert driver.servos["elbow"].position == pytest.approx(-0.5, abs=1e-3)
    assert driver.servos["shoulder"].position == pytest.approx(0.6, abs=1e-3)
    last = dict(zip(states[-1].name, states[-1].position, strict=True))
    assert last["elbow"] == pytest.approx(-0.5, abs=1e-3)
    # While a trajectory owns the joints, <joint>/command is ignored; afterwards it works.
    probe.publisher("/elbow/command", "std_msgs/Float64").publish_data({"data": 0.0})
    graph.run(duration=1.0)
    assert driver.servos["elbow"].position == pytest.approx(0.0)


def test_follow_controller_velocity_mode_preempt_and_bad_goals() -> None:
    graph = Graph()
    driver, probe = _arm(graph)
    client = ActionClient(
        probe, "/arm_controller/follow_joint_trajectory", "control_msgs/FollowJointTrajectory"
    )
    slow = client.send_goal(
        {
            "trajectory": {
                "joint_names": ["shoulder", "elbow"],
                "points": [{"positions": [1.0, 0.0], "velocities": [0.5, 0.5]}],
            }
        }
    )
    graph.run(duration=0.5)
    assert driver.servos["shoulder"].position == pytest.approx(0.25, abs=0.02)
    newer = client.send_goal(
        {
            "trajectory": {
                "joint_names": ["shoulder", "elbow"],
                "points": [{"positions": [0.0, 0.0], "time_from_start": [0, 500_000_000]}],
            }
        }
    )
    graph.run(duration=1.0)
    assert client.status[slow] is GoalStatus.PREEMPTED
    assert client.status[newer] is GoalStatus.SUCCEEDED
    assert driver.servos["shoulder"].position == pytest.approx(0.0, abs=1e-3)
    missing = client.send_goal({"trajectory": {"joint_names": ["shoulder"], "points": [{}]}})
    empty = client.send_goal({"trajectory": {"joint_names": ["shoulder", "elbow"]}})
    zero_speed = client.send_goal(
        {
            "trajectory": {
                "joint_names": ["shoulder", "elbow"],
                "points": [{"positions": [1.0, 0.0], "velocities": [0.0, 1.0]}],
            }
        }
    )
    graph.run(duration=0.5)
    assert [client.status[g] for g in (missing, empty, zero_speed)] == [GoalStatus.ABORTED] * 3
    assert "missing ['elbow']" in client.results[missing].status.text
    # Cancel a running goal.
    running = client.send_goal(
        {
            "trajectory": {
                "joint_names": ["shoulder", "elbow"],
                "points": [{"positions": [1.0, 1.0], "time_from_start": [5, 0]}],
            }
        }
    )
    graph.run(duration=0.5)
    client.cancel(running)
    graph.run(duration=0.5)
    assert client.status[running] is GoalStatus.PREEMPTED
    assert 0.0 < driver.servos["shoulder"].position < 0.2


def test_joint_trajectory_topic() -> None:
    graph = Graph()
    driver, probe = _arm(graph)
    probe.publisher("/arm_controller/command", "trajectory_msgs/JointTrajectory").publish_data(
        {
            "joint_names": ["shoulder", "elbow"],
            "points": [{"positions": [0.2, -0.2], "time_from_start": [1, 0]}],
        }
    )
    graph.run(duration=1.5)
    assert driver.servos["shoulder"].position == pytest.approx(0.2, abs=1e-3)
    assert driver.servos["elbow"].position == pytest.approx(-0.2, abs=1e-3)


def test_course_and_rbx1_configs_load() -> None:
    mbot = ArbotixConfig.from_yaml(load_yaml_file(MBOT_YAML))
    (base,) = mbot.controllers
    assert isinstance(base, DiffControllerConfig)
    assert (base.name, base.base_frame_id, base.rate) == ("base_controller", "base_footprint", 10)
    rbx1 = ArbotixConfig.from_yaml(load_yaml_file(RBX1_YAML))
    assert (rbx1.rate, rbx1.read_rate, rbx1.write_rate) == (20, 20, 20)


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        (
            "controllers: {\n  base: {type: diff_controller,\n    base_width: 0.2}\n}\n",
            r"arbotix\.yaml:2:9",
            "controllers/base: required parameter 'ticks_meter' is missing",
        ),
        (
            "controllers:\n  base:\n    type: diff_controller\n    ticks_meter: 1\n",
            r"arbotix\.yaml:3:5",
            "required parameter 'base_width' is missing",
        ),
        (
            "controllers:\n  base: {type: omni_controller}\n",
            r"arbotix\.yaml:2:16",
            "unknown type 'omni_controller'",
        ),
        (
            "rate: fast\n",
            r"arbotix\.yaml:1:7",
            "parameter rate: expected a number, got 'fast'",
        ),
        (
            "controllers:\n  base: {type: diff_controller, ticks_meter: 1, base_width: 1,"
            " rate: 0}\n",
            r"arbotix\.yaml:2:70",
            "expected a positive number",
        ),
        (
            "joints: {a: {id: 1}}\ncontrollers:\n  arm: {type: follow_controller,"
            " joints: [a, b]}\n",
            r"arbotix\.yaml:3:46",
            "joint 'b' is not one of the driver's joints",
        ),
        ("controllers: {\n  base: [1,\n}\n", r"arbotix\.yaml:3:1", "invalid YAML"),
    ],
)
def test_bad_config_names_file_and_line(
    tmp_path: Path, text: str, where: str, message: str
) -> None:
    path = tmp_path / "arbotix.yaml"
    path.write_text(text)
    with pytest.raises(ParseError, match=where) as info:
        ArbotixConfig.from_yaml(load_yaml_file(path))
    assert message in str(info.value)


def test_config_from_the_parameter_tree_names_the_parameter() -> None:
    graph = Graph()
    node = graph.create_node(
        "arbotix", namespace="/r1", params={"controllers": {"b": {"type": "diff_controller"}}}
    )
    with pytest.raises(ArbotixConfigError, match=r"parameter /r1/arbotix/controllers/b"):
        ArbotixDriver(node)


def test_hardware_only_controllers_are_skipped() -> None:
    config = ArbotixConfig.from_params(
        {"sim": True, "controllers": {"gripper": {"type": "linear_controller"}}}
    )
    assert config.controllers == ()
    assert config.skipped == (
        "gripper (linear_controller reads ArbotiX analog inputs: hardware only)",
    )


def test_default_config_from_the_model() -> None:
    config = default_config(RobotModel.from_path(MBOT))
    (base,) = config.controllers
    assert isinstance(base, DiffControllerConfig)
    assert base.base_frame_id == "base_footprint"
    assert base.base_width == pytest.approx(0.38)


def test_several_robots_in_namespaces() -> None:
    graph = Graph()
    model = RobotModel.from_path(TURTLEBOT)
    doc = load_yaml_file(RBX1_YAML)
    config = ArbotixConfig.from_yaml(doc)
    robots = [
        KinematicSimulation(graph, model, config, params=doc.data, namespace=ns)
        for ns in ("r1", "r2")
    ]
    probe = graph.create_node("probe")
    listener = TransformListener(probe, TFBuffer())
    _drive(graph, probe, 0.5, 0.0, "/r1/cmd_vel")
    _drive(graph, probe, 0.0, 1.0, "/r2/cmd_vel")
    odom = _collect(probe, "/r2/odom", "nav_msgs/Odometry")
    graph.run(duration=2.0)
    r1, r2 = (r.driver.base for r in robots)
    assert r1 is not None
    assert r2 is not None
    assert r1.x == pytest.approx(1.0)
    assert r1.th == 0.0
    assert r2.x == 0.0
    assert r2.th == pytest.approx(2.0)
    assert odom[-1].header.frame_id == "r2/odom"
    assert odom[-1].child_frame_id == "r2/base_footprint"
    t = listener.buffer.lookup_transform("r1/odom", "r1/camera_link")
    assert t.translation[0] == pytest.approx(1.0 - 0.05)
    assert graph.params.has("/r1/robot_description")
    assert graph.params.get("/r2/arbotix/rate") == 20


def _arbotix_warning(record: logging.LogRecord) -> bool:
    # robot_state_publisher warns too, as ROS's does, about the wheel joints arbotix reports
    # that the mbot names otherwise
    return record.name == "belvedere.arbotix" and record.levelno >= logging.WARNING
