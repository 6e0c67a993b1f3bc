"""The physics engine with the course's mbot: resting, driving, turning, odometry, TF,
joint states, determinism, bad commands, bad models and gazebo_ros's services."""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import Any

import pytest

from belvedere.cli import main
from belvedere.description.urdf import Pose, RobotModel
from belvedere.graph import Graph, Node
from belvedere.msgs import types
from belvedere.packages import PackageIndex
from belvedere.sim.physics import GazeboRos, ModelError, PhysicsSimulation, spawn_model
from belvedere.world import read_world
from tests.conftest import EXAMPLES

MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"
EMPTY = EXAMPLES / "mbot_gazebo/worlds/empty.world"


def _yaw(pose: Any) -> float:
    q = pose.orientation
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


class Scene:
    def __init__(self, urdf: str | None = None, *, seed: int = 0) -> None:
        self.graph = Graph(seed=seed)
        self.sim = PhysicsSimulation(self.graph, read_world(EMPTY))
        self.model = (
            RobotModel.from_string(urdf) if urdf is not None else RobotModel.from_path(MBOT)
        )
        self.robot = self.sim.spawn(self.model, name="mbot")
        self.probe: Node = self.graph.create_node("probe")
        self.odom: list[Any] = []
        self.tf: list[Any] = []
        self.states: list[Any] = []
        self.probe.subscribe("/odom", "nav_msgs/Odometry", self.odom.append, queue_size=0)
        self.probe.subscribe("/tf", "tf2_msgs/TFMessage", self.tf.append, queue_size=0)
        self.probe.subscribe(
            "/joint_states", "sensor_msgs/JointState", self.states.append, queue_size=0
        )
        self.cmd = self.probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)

    def drive(self, x: float = 0.0, z: float = 0.0) -> None:
        self.cmd.publish_data({"linear": {"x": x}, "angular": {"z": z}})


@pytest.fixture(scope="module")
def driven() -> Scene:
    """Rest 1 s, x=0.2 for 5 s, then z=0.5 for 3 s."""
    scene = Scene()
    scene.graph.run(duration=1.0)
    scene.rest = scene.odom[-1]  # type: ignore[attr-defined]
    scene.drive(x=0.2)
    scene.graph.run(duration=5.0)
    scene.straight = scene.odom[-1]  # type: ignore[attr-defined]
    scene.drive(z=0.5)
    scene.graph.run(duration=1.0)
    scene.turn_start = scene.odom[-1]  # type: ignore[attr-defined]
    scene.graph.run(duration=2.0)
    scene.turn_end = scene.odom[-1]  # type: ignore[attr-defined]
    return scene


def test_rests_on_casters_and_wheels(driven: Scene) -> None:
    p = driven.rest.pose.pose  # type: ignore[attr-defined]
    assert math.hypot(p.position.x, p.position.y) < 1e-4
    assert abs(p.position.z) < 2e-3
    assert abs(_yaw(p)) < 1e-4
    q = p.orientation
    assert abs(q.x) < 1e-3  # upright: no roll or pitch
    assert abs(q.y) < 1e-3


def test_drives_one_metre_in_five_seconds(driven: Scene) -> None:
    start = driven.rest.pose.pose.position  # type: ignore[attr-defined]
    end = driven.straight.pose.pose.position  # type: ignore[attr-defined]
    assert end.x - start.x == pytest.approx(1.0, rel=0.03)
    assert abs(end.y - start.y) < 0.01


def test_turns_counter_clockwise_at_half_a_radian_per_second(driven: Scene) -> None:
    # The course's mbot has its "left" wheel on the right and sets legacyMode: as Gazebo 7
    # did, that swaps the wheels back, so angular.z > 0 turns it counter-clockwise.
    a = driven.turn_start  # type: ignore[attr-defined]
    b = driven.turn_end  # type: ignore[attr-defined]
    rate = (_yaw(b.pose.pose) - _yaw(a.pose.pose)) / 2.0
    assert rate == pytest.approx(0.5, rel=0.05)
    assert b.twist.twist.angular.z == pytest.approx(0.5, rel=0.05)


def test_odometry_rate_frames_wheel_tf_and_joint_states(driven: Scene) -> None:
    stamps = [m.header.stamp.sec + m.header.stamp.nanosec * 1e-9 for m in driven.odom]
    in_last_second = [t for t in stamps if t > stamps[-1] - 1.0]
    assert len(in_last_second) == 100
    last = driven.odom[-1]
    assert (last.header.frame_id, last.child_frame_id) == ("odom", "base_footprint")
    assert list(last.pose.covariance[[0, 7, 35]]) == [1e-5, 1e-5, 1e-3]
    pairs = {(t.header.frame_id, t.child_frame_id) for m in driven.tf for t in m.transforms}
    assert ("odom", "base_footprint") in pairs
    assert ("base_link", "left_wheel_link") in pairs  # publishWheelTF
    wheel_states = [
        s for s in driven.states if list(s.name) == ["left_wheel_joint", "right_wheel_joint"]
    ]
    assert len(wheel_states) > 500  # publishWheelJointState at 100 Hz
    assert len(wheel_states[-1].velocity) == 0  # positions only, as the original


def test_without_legacy_mode_the_course_robot_turns_clockwise() -> None:
    urdf = RobotModel.from_path(MBOT).to_urdf().replace("<legacyMode>true</legacyMode>", "")
    scene = Scene(urdf)
    scene.graph.run(duration=0.5)
    scene.drive(z=0.5)
    scene.graph.run(duration=2.0)
    assert _yaw(scene.odom[-1].pose.pose) < -0.5  # Melodic/Noetic semantics


def test_same_seed_same_run() -> None:
    runs = []
    for _ in range(2):
        scene = Scene(seed=7)
        scene.drive(x=0.3, z=0.2)
        scene.graph.run(duration=1.5)
        runs.append([types().serialize(m) for m in scene.odom])
    assert runs[0] == runs[1]


def test_non_finite_commands_keep_the_last_one(caplog: pytest.LogCaptureFixture) -> None:
    scene = Scene()
    scene.drive(x=0.2)
    scene.graph.run(duration=1.0)
    caplog.set_level(logging.WARNING, logger="belvedere.physics")
    # 1e154 m/s used to make MuJoCo reset the robot to the origin mid-run, unreported.
    for bad in ({"linear": {"x": float("nan")}}, {"angular": {"z": float("inf")}}):
        scene.cmd.publish_data(bad)
        scene.graph.run(duration=0.1)
    scene.cmd.publish_data({"linear": {"x": 1e154}})
    scene.graph.run(duration=0.8)
    assert scene.odom[-1].twist.twist.linear.x == pytest.approx(0.2, rel=0.02)
    assert [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING] == [
        "differential_drive_controller: ignored a command with linear.x=nan (not finite); "
        "keeping the last one"
    ]
    assert scene.sim.stopped_reason is None


def test_a_state_mujoco_gives_up_on_is_reported_as_divergence(
    caplog: pytest.LogCaptureFixture, capfd: pytest.CaptureFixture[str]
) -> None:
    scene = Scene()
    scene.drive(x=0.2)
    scene.graph.run(duration=1.0)
    engine = scene.sim.engine
    assert scene.robot.build.free_joint is not None
    base = engine.joint(scene.robot.build.free_joint)
    engine.d.qvel[base.dof] = 1e12  # beyond what MuJoCo integrates: it resets the world
    caplog.set_level(logging.ERROR, logger="belvedere.physics")
    scene.graph.run(duration=0.5)
    reason = scene.sim.stopped_reason
    assert reason is not None
    assert reason.startswith(
        "MuJoCo found a NaN, infinite or huge velocity of body 'mbot/base_footprint' and reset "
        "the world to its start; the inertia of link "
    )
    [record] = [r for r in caplog.records if r.levelno >= logging.ERROR]
    assert record.getMessage().startswith("physics diverged at t=1.001 s: MuJoCo found")
    # MuJoCo's own printout (and its MUJOCO_LOG.TXT) stay out of the user's output.
    assert capfd.readouterr().out == ""


UNPHYSICAL = """<robot name="bad">
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="5"/>
    </inertial>
  </link>
</robot>"""


def test_unphysical_inertia_is_refused_with_its_line() -> None:
    graph = Graph()
    sim = PhysicsSimulation(graph)
    with pytest.raises(ModelError, match=r"robot\.urdf:3:.*inertia of link 'base'"):
        sim.spawn(RobotModel.from_string(UNPHYSICAL, path="robot.urdf"))


def test_unknown_plugin_is_one_warning_and_the_rest_runs(
    caplog: pytest.LogCaptureFixture,
) -> None:
    urdf = (
        RobotModel.from_path(MBOT)
        .to_urdf()
        .replace(
            "</robot>",
            '<gazebo><plugin name="mystery" filename="libmystery_plugin.so"/></gazebo></robot>',
        )
    )
    caplog.set_level(logging.WARNING, logger="belvedere.physics")
    scene = Scene(urdf)
    scene.graph.run(duration=0.2)
    warnings = [r.getMessage() for r in caplog.records if "libmystery_plugin.so" in r.getMessage()]
    assert len(warnings) == 1
    assert "unknown plugin" in warnings[0]
    assert ":" in warnings[0].split(" ")[0]  # file:line first
    assert len(scene.odom) == 19  # the diff drive still runs


def test_divergence_is_reported_and_the_physics_stops(caplog: pytest.LogCaptureFixture) -> None:
    urdf = """<robot name="spinner">
      <link name="base"><inertial><mass value="1"/>
        <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
        <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
    </robot>"""
    graph = Graph()
    sim = PhysicsSimulation(graph)
    sim.spawn(RobotModel.from_string(urdf, path="spinner.urdf"), pose=Pose((0, 0, 1.0)))
    caplog.set_level(logging.ERROR, logger="belvedere.physics")
    graph.run(duration=0.01)
    sim.engine.d.qvel[3:6] = [1e9, 0, 0]  # a kick nothing physical gives
    graph.run(duration=0.1)
    assert sim.stopped_reason is not None
    assert "spinner.urdf" in sim.stopped_reason
    assert any("physics diverged" in r.getMessage() for r in caplog.records)
    t = graph.now_ns()
    graph.run(duration=0.1)  # the graph keeps running; the physics stays stopped
    assert graph.now_ns() > t


def test_gazebo_services() -> None:
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world(EMPTY))
    GazeboRos(sim, packages=PackageIndex([EXAMPLES]))
    node = graph.create_node("client")
    graph.params.set("/robot_description", RobotModel.from_path(MBOT).to_urdf())
    response = spawn_model(
        node, ["-urdf", "-param", "robot_description", "-model", "mbot", "-x", "1", "-Y", "1.57"]
    )
    assert response.success
    graph.run(duration=0.5)
    state = node.call_service(
        "/gazebo/get_model_state", "gazebo_msgs/GetModelState", {"model_name": "mbot"}
    )
    assert state.success
    assert state.pose.position.x == pytest.approx(1.0, abs=1e-3)
    assert _yaw(state.pose) == pytest.approx(1.57, abs=1e-3)
    moved = node.call_service(
        "/gazebo/set_model_state",
        "gazebo_msgs/SetModelState",
        {
            "model_state": {
                "model_name": "mbot",
                "pose": {"position": {"x": -2.0}, "orientation": {"w": 1.0}},
            }
        },
    )
    assert moved.success
    graph.run(duration=0.2)
    assert sim.model_pose("mbot")[0, 3] == pytest.approx(-2.0, abs=1e-3)
    missing = node.call_service(
        "/gazebo/get_model_state", "gazebo_msgs/GetModelState", {"model_name": "nope"}
    )
    assert not missing.success
    assert "no model named 'nope'" in missing.status_message
    props = node.call_service("/gazebo/get_physics_properties", "gazebo_msgs/GetPhysicsProperties")
    assert (props.time_step, props.gravity.z) == (0.001, -9.8)
    sdf = (EXAMPLES / "mbot_gazebo/models/belvedere_crate/model.sdf").read_text()
    crate = node.call_service(
        "/gazebo/spawn_sdf_model",
        "gazebo_msgs/SpawnModel",
        {"model_name": "crate", "model_xml": sdf, "initial_pose": {"position": {"x": 3.0}}},
    )
    assert crate.success, crate.status_message
    graph.run(duration=0.5)
    assert sim.model_pose("crate")[:3, 3] == pytest.approx([3.0, 0.0, 0.0], abs=1e-2)
    node.call_service("/gazebo/reset_world", "std_srvs/Empty")
    graph.run(duration=0.01)
    deleted = node.call_service(
        "/gazebo/delete_model", "gazebo_msgs/DeleteModel", {"model_name": "crate"}
    )
    assert deleted.success
    assert "crate" not in sim.model_names()
    graph.run(duration=0.1)
    bad = node.call_service(
        "/gazebo/spawn_urdf_model",
        "gazebo_msgs/SpawnModel",
        {"model_name": "x", "model_xml": "<robot name='x'><link name='a'>"},
    )
    assert not bad.success
    assert "malformed XML" in bad.status_message


def _wheeled(mass: str) -> str:
    inertia = '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>'
    return f"""<robot name="w">
  <link name="base"><inertial><mass value="1"/>{inertia}</inertial></link>
  <link name="wheel">
    <inertial><mass value="{mass}"/>{inertia}</inertial>
  </link>
  <joint name="axle" type="continuous"><parent link="base"/><child link="wheel"/></joint>
</robot>"""


def test_a_massless_moving_link_is_one_warning_at_its_line(
    endpoint: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "w.urdf"
    path.write_text(_wheeled("0"))
    args = ["sim", str(path), "--engine", "physics", "--headless", "--duration", "0.1"]
    assert main([*args, "--rtf", "max"]) == 0
    err = capsys.readouterr().err
    assert (
        f"{path}:4:5: warning: link 'wheel' (and the links fixed to it) has no mass; "
        "simulating it with 0.001 kg\n"
    ) in err
    path.write_text(_wheeled("-20"))
    assert main(args) == 1
    assert capsys.readouterr().err.endswith(
        f"{path}:4:5: error: the mass of link 'wheel' is -20 kg: no body has less than 0\n"
    )


def _recorded(batched: bool) -> tuple[list[Any], list[Any], int]:
    """Odometry, scans and the step count of the laser mbot driving in the box room."""
    xacro = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
    graph = Graph(seed=3)
    world = read_world(EXAMPLES / "mbot_gazebo/worlds/box_room.world")
    sim = PhysicsSimulation(graph, world)
    sim.spawn(RobotModel.from_path(xacro), name="mbot")
    if not batched:
        sim.every_step.append(lambda: True)
    probe = graph.create_node("probe")
    odom: list[Any] = []
    scans: list[Any] = []
    probe.subscribe("/odom", "nav_msgs/Odometry", odom.append, queue_size=0)
    probe.subscribe("/scan", "sensor_msgs/LaserScan", scans.append, queue_size=0)
    cmd = probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    graph.run(duration=0.5)
    cmd.publish_data({"linear": {"x": 0.2}, "angular": {"z": 0.4}})
    graph.run(duration=1.5)
    return odom, scans, sim.steps


def test_batched_steps_give_the_same_run_as_single_steps() -> None:
    """Physics runs the steps between plugin updates in one batch: bit for bit the same."""
    batched, single = _recorded(batched=True), _recorded(batched=False)
    registry = types()
    for got, want in zip(batched[:2], single[:2], strict=True):
        assert len(got) == len(want) > 0
        assert [registry.serialize(m) for m in got] == [registry.serialize(m) for m in want]
    assert batched[2] == single[2] == 2000
