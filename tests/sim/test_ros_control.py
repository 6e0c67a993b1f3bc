"""ros_control in the physics engine: the marm arm with position and trajectory controllers,
effort PID controllers, and the mbot on a diff_drive_controller."""

from __future__ import annotations

import logging
import math
from typing import Any

import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import ActionClient, GoalStatus, Graph
from belvedere.sim.physics import ModelError, PhysicsSimulation, spawner
from belvedere.yamlfile import load_yaml_file
from tests.conftest import EXAMPLES

MARM = EXAMPLES / "marm_description/urdf/marm.xacro"
CONTROLLERS = EXAMPLES / "marm_description/config/marm_controllers.yaml"
MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"


def _arm(urdf: str | None = None) -> tuple[Graph, PhysicsSimulation, Any]:
    graph = Graph()
    for key, value in load_yaml_file(CONTROLLERS).data.items():
        graph.params.set(f"/{key}", value)
    sim = PhysicsSimulation(graph)
    model = RobotModel.from_string(urdf) if urdf else RobotModel.from_path(MARM)
    sim.spawn(model, name="marm")
    return graph, sim, graph.create_node("client")


def _joint(sim: PhysicsSimulation, name: str) -> float:
    robot = sim.robots["marm"]
    ref = sim.engine.joint(robot.build.joints[name])
    return float(sim.engine.d.qpos[ref.qpos])


def test_position_controllers_reach_their_commands() -> None:
    graph, sim, client = _arm()
    started = spawner(
        client,
        ["joint_state_controller", "joint1_position_controller", "joint2_position_controller"],
        namespace="/marm",
    )
    assert started == [
        "joint_state_controller",
        "joint1_position_controller",
        "joint2_position_controller",
    ]
    states: list[Any] = []
    client.subscribe("/marm/joint_states", "sensor_msgs/JointState", states.append)
    client.publisher("/marm/joint1_position_controller/command", "std_msgs/Float64").publish_data(
        {"data": 1.0}
    )
    client.publisher("/marm/joint2_position_controller/command", "std_msgs/Float64").publish_data(
        {"data": -0.5}
    )
    graph.run(duration=2.0)
    assert _joint(sim, "joint1") == pytest.approx(1.0, abs=0.01)
    assert _joint(sim, "joint2") == pytest.approx(-0.5, abs=0.01)
    assert len(states) == 100  # publish_rate 50
    last = dict(zip(states[-1].name, states[-1].position, strict=True))
    assert last["joint1"] == pytest.approx(1.0, abs=0.01)
    listed = client.call_service(
        "/marm/controller_manager/list_controllers", "controller_manager_msgs/ListControllers"
    )
    assert {c.name: c.state for c in listed.controller} == {
        "joint_state_controller": "running",
        "joint1_position_controller": "running",
        "joint2_position_controller": "running",
    }
    claimed = {
        c.name: [(r.hardware_interface, list(r.resources)) for r in c.claimed_resources]
        for c in listed.controller
    }
    assert claimed == {
        "joint_state_controller": [("hardware_interface::JointStateInterface", [])],
        "joint1_position_controller": [("hardware_interface::PositionJointInterface", ["joint1"])],
        "joint2_position_controller": [("hardware_interface::PositionJointInterface", ["joint2"])],
    }


def test_trajectory_controller_follows_a_trajectory() -> None:
    graph, sim, client = _arm()
    spawner(client, ["joint_state_controller", "arm_controller"], namespace="/marm")
    action = ActionClient(
        client, "/marm/arm_controller/follow_joint_trajectory", "control_msgs/FollowJointTrajectory"
    )
    joints = ["joint1", "joint2", "joint3", "joint4", "joint5", "joint6"]
    goal = action.send_goal(
        {
            "trajectory": {
                "joint_names": joints,
                "points": [
                    {"positions": [0.5, 0.3, -0.4, 0.2, 0.1, 0.0], "time_from_start": [1, 0]},
                    {"positions": [1.0, 0.6, -0.8, 0.4, 0.2, 0.5], "time_from_start": [2, 0]},
                ],
            }
        }
    )
    graph.run(duration=0.5)
    # halfway through the first segment: halfway to its positions (linear interpolation)
    assert _joint(sim, "joint1") == pytest.approx(0.25, abs=0.03)
    graph.run(duration=2.0)
    assert action.status[goal] is GoalStatus.SUCCEEDED
    for name, target in zip(joints, [1.0, 0.6, -0.8, 0.4, 0.2, 0.5], strict=True):
        assert _joint(sim, name) == pytest.approx(target, abs=0.01), name


EFFORT_ARM = """<robot name="pendulum">
  <link name="world"/>
  <joint name="fix" type="fixed"><parent link="world"/><child link="base"/></joint>
  <link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="swing" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 1 0"/><limit effort="20" velocity="5" lower="-3" upper="3"/></joint>
  <link name="arm"><inertial><origin xyz="0 0 0.2"/><mass value="0.5"/>
    <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.0001"/></inertial></link>
  <transmission name="t"><type>transmission_interface/SimpleTransmission</type>
    <joint name="swing"><hardwareInterface>EffortJointInterface</hardwareInterface></joint>
    <actuator name="m"/></transmission>
  <gazebo><plugin name="rc" filename="libgazebo_ros_control.so">
    <robotNamespace>/marm</robotNamespace></plugin></gazebo>
</robot>"""


def test_effort_pid_position_controller_holds_against_gravity() -> None:
    graph = Graph()
    graph.params.set(
        "/marm/swing_controller",
        {
            "type": "effort_controllers/JointPositionController",
            "joint": "swing",
            "pid": {"p": 100.0, "i": 10.0, "d": 5.0, "i_clamp": 5.0},
        },
    )
    sim = PhysicsSimulation(graph)
    sim.spawn(RobotModel.from_string(EFFORT_ARM), name="marm")
    client = graph.create_node("client")
    spawner(client, ["swing_controller"], namespace="/marm")
    client.publisher("/marm/swing_controller/command", "std_msgs/Float64").publish_data(
        {"data": 0.8}
    )
    graph.run(duration=4.0)
    assert _joint(sim, "swing") == pytest.approx(0.8, abs=0.01)


def test_missing_gains_and_bad_controllers(caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.WARNING, logger="belvedere.ros_control")
    graph, _sim, client = _arm()
    warnings = [r for r in caplog.records if "no PID gains" in r.getMessage()]
    assert len(warnings) == 1  # one line for every joint, not a flood
    graph.params.set(
        "/marm/bad_pid", {"type": "effort_controllers/JointPositionController", "joint": "joint1"}
    )
    graph.params.set("/marm/unknown", {"type": "mystery_controllers/Thing"})
    for name in ("bad_pid", "unknown", "not_configured"):
        with pytest.raises(ModelError, match=f"failed to load controller {name!r}"):
            spawner(client, [name], namespace="/marm")
    messages = " ".join(r.getMessage() for r in caplog.records)
    assert "needs PID gains: /marm/bad_pid/pid/p" in messages
    assert "unknown type 'mystery_controllers/Thing'" in messages
    assert "no parameter /marm/not_configured/type" in messages


DIFF_DRIVE_PARAMS = {
    "type": "diff_drive_controller/DiffDriveController",
    "left_wheel": "right_wheel_joint",  # the course robot's "left" wheel is on the right
    "right_wheel": "left_wheel_joint",
    "publish_rate": 50,
    "base_frame_id": "base_footprint",
    "cmd_vel_timeout": 0.5,
}


def test_diff_drive_controller_drives_and_times_out() -> None:
    urdf = RobotModel.from_path(MBOT).to_urdf()
    start = urdf.index('<plugin filename="libgazebo_ros_diff_drive.so"')
    end = urdf.index("</plugin>", start) + len("</plugin>")
    urdf = (
        urdf[:start]
        + '<plugin name="rc" filename="libgazebo_ros_control.so">'
        + "<robotNamespace>/</robotNamespace></plugin>"
        + urdf[end:]
    )
    for side in ("left", "right"):  # ros_control wants effort limits on its joints
        joint = f'<joint name="{side}_wheel_joint" type="continuous">'
        urdf = urdf.replace(joint, joint + '<limit effort="20" velocity="20"/>')
    graph = Graph()
    graph.params.set("/mobile_base_controller", DIFF_DRIVE_PARAMS)
    sim = PhysicsSimulation(graph)
    sim.spawn(RobotModel.from_string(urdf), name="mbot")
    client = graph.create_node("client")
    spawner(client, ["mobile_base_controller"])
    odom: list[Any] = []
    client.subscribe("/mobile_base_controller/odom", "nav_msgs/Odometry", odom.append)
    cmd = client.publisher("/mobile_base_controller/cmd_vel", "geometry_msgs/Twist")
    for k in range(20):  # 0.2 m/s for 2 s, commands at 10 Hz
        client.timer(0.1 * (k + 1), lambda: cmd.publish_data({"linear": {"x": 0.2}}), oneshot=True)
    graph.run(duration=2.05)
    x = odom[-1].pose.pose.position.x
    assert x == pytest.approx(0.4, abs=0.04)  # wheel odometry, from the wheels' positions
    truth = sim.model_pose("mbot")[0, 3]
    assert truth == pytest.approx(x, abs=0.02)
    graph.run(duration=2.0)  # no commands: 0.5 s more (cmd_vel_timeout), then it brakes
    assert odom[-1].pose.pose.position.x == pytest.approx(x + 0.1, abs=0.03)
    assert abs(odom[-1].twist.twist.linear.x) < 0.01
    assert math.isfinite(odom[-1].pose.pose.orientation.w)
