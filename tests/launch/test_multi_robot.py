"""The multi-robot example (mbot_gazebo multi_mbot.launch): each robot in its own
``<group ns>`` has its own cmd_vel, odom and scan, frames under its ``tf_prefix`` and a
connected TF tree (joined to the others at ``world``), and moves on its own commands only."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from belvedere.description.urdf import Pose
from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from belvedere.sim.physics import parse_spawn_args
from belvedere.tf import TransformListener
from tests.conftest import EXAMPLES

LAUNCH = EXAMPLES / "mbot_gazebo/launch/multi_mbot.launch"
ROBOTS = ("robot_1", "robot_2", "robot_3")
START_Y = {"robot_1": 0.0, "robot_2": 1.5, "robot_3": -1.5}


@pytest.fixture(scope="module")
def driven() -> Any:
    """The launch run for 2 simulated seconds with robot_2 told to drive forward and robot_3
    to turn on the spot; robot_1 has no command."""
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(LAUNCH, packages=packages), graph, packages, headless=True)
    runtime.start()
    assert not runtime.missing
    probe = graph.create_node("probe")
    odom: dict[str, list[Any]] = {r: [] for r in ROBOTS}
    scans: dict[str, list[Any]] = {r: [] for r in ROBOTS}
    for robot in ROBOTS:
        probe.subscribe(f"/{robot}/odom", "nav_msgs/Odometry", odom[robot].append, queue_size=0)
        probe.subscribe(
            f"/{robot}/scan", "sensor_msgs/LaserScan", scans[robot].append, queue_size=0
        )
    tf = TransformListener(probe)
    commands = {
        "robot_2": {"linear": {"x": 0.3}},
        "robot_3": {"angular": {"z": 0.8}},
    }
    for robot, twist in commands.items():
        probe.publisher(f"/{robot}/cmd_vel", "geometry_msgs/Twist", latch=True).publish_data(twist)
    graph.run(duration=2.0)
    yield graph, odom, scans, tf.buffer
    runtime.close()
    graph.shutdown()


def _xy_yaw(msg: Any) -> tuple[float, float, float]:
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
    return p.x, p.y, yaw


def test_each_robot_has_its_own_topics(driven: Any) -> None:
    graph, odom, scans, _ = driven
    for robot in ROBOTS:
        for topic in ("cmd_vel", "odom", "scan", "joint_states"):
            assert f"/{robot}/{topic}" in graph.topics, f"/{robot}/{topic}"
    # nothing of the robots is left on the single-robot names
    for topic in ("/cmd_vel", "/odom", "/scan"):
        assert topic not in graph.topics, topic
    for robot in ROBOTS:
        assert odom[robot], f"no odometry from {robot}"
        assert scans[robot], f"no scan from {robot}"


def test_frames_carry_the_tf_prefix(driven: Any) -> None:
    _, odom, scans, _ = driven
    for robot in ROBOTS:
        last = odom[robot][-1]
        assert (last.header.frame_id, last.child_frame_id) == (
            f"{robot}/odom",
            f"{robot}/base_footprint",
        )
        assert scans[robot][-1].header.frame_id == f"{robot}/laser_link"


def test_each_tf_tree_is_connected(driven: Any) -> None:
    _, _, _, buffer = driven
    for robot in ROBOTS:
        for link in ("laser_link", "left_wheel_link", "back_caster_link"):
            ok, why = buffer.can(f"{robot}/odom", f"{robot}/{link}", 0)
            assert ok, f"{robot}/odom -> {robot}/{link}: {why}"
        # the laser sits 0.105 m above base_link, whatever the robot's pose
        _, position, _ = buffer.lookup(f"{robot}/base_link", f"{robot}/laser_link", 0)
        assert position == pytest.approx((0.0, 0.0, 0.105), abs=1e-6)
    # the example's static world -> robot_i/odom joins them where Gazebo puts the robots
    for robot in ROBOTS:
        _, position, _ = buffer.lookup("world", f"{robot}/base_footprint", 0)
        assert position[1] == pytest.approx(START_Y[robot], abs=0.05), robot


def test_each_robot_moves_on_its_own_commands_only(driven: Any) -> None:
    _, odom, _, _ = driven
    x1, y1, yaw1 = _xy_yaw(odom["robot_1"][-1])
    assert (x1, y1) == pytest.approx((0.0, START_Y["robot_1"]), abs=0.02)
    assert yaw1 == pytest.approx(0.0, abs=0.05)
    x2, y2, yaw2 = _xy_yaw(odom["robot_2"][-1])
    assert x2 > 0.3, "robot_2 drove forward on /robot_2/cmd_vel"
    assert y2 == pytest.approx(START_Y["robot_2"], abs=0.05)
    assert yaw2 == pytest.approx(0.0, abs=0.1)
    x3, y3, yaw3 = _xy_yaw(odom["robot_3"][-1])
    assert (x3, y3) == pytest.approx((0.0, START_Y["robot_3"]), abs=0.05)
    assert abs(yaw3) > 0.5, "robot_3 turned on /robot_3/cmd_vel"


def test_spawn_model_defaults_the_robot_namespace_to_its_own() -> None:
    """As rospy.get_namespace() is spawn_model's default: None here, the spawner's
    namespace when the call is made."""
    assert parse_spawn_args(["-model", "a"]).robot_namespace is None
    given = parse_spawn_args(["-model", "a", "-robot_namespace", "/x"])
    assert given.robot_namespace == "/x"


def test_a_plugin_naming_its_namespace_keeps_it_in_a_spawner_namespace() -> None:
    """Gazebo's spawn service gives the spawner's namespace only to plugins without a
    ``<robotNamespace>``: the unchanged course robot (its diff drive says ``/``) spawned for
    /robot_9 keeps /cmd_vel and /odom, while its laser goes to /robot_9/scan; every frame
    takes the tf_prefix searched from the plugin's namespace."""
    from belvedere.description.urdf import RobotModel
    from belvedere.sim.physics import PhysicsSimulation

    xacro = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
    graph = Graph()
    graph.params.set("/robot_9/tf_prefix", "robot_9")
    sim = PhysicsSimulation(graph)
    sim.spawn(RobotModel.from_path(xacro), name="robot_9", robot_namespace="/robot_9/")
    probe = graph.create_node("probe")
    odom: list[Any] = []
    scans: list[Any] = []
    probe.subscribe("/odom", "nav_msgs/Odometry", odom.append)
    probe.subscribe("/robot_9/scan", "sensor_msgs/LaserScan", scans.append)
    graph.run(duration=0.5)
    assert "/cmd_vel" in graph.topics
    assert "/robot_9/cmd_vel" not in graph.topics
    # the diff drive's namespace is / (no tf_prefix there), the laser's /robot_9
    assert (odom[-1].header.frame_id, odom[-1].child_frame_id) == ("odom", "base_footprint")
    assert scans[-1].header.frame_id == "robot_9/laser_link"
    graph.shutdown()


def test_a_saved_world_keeps_each_robots_namespace(tmp_path: Path) -> None:
    """As Gazebo's rewritten SDF does: the namespace the spawner gave the laser is written
    into the saved world, so the robots come back on their own topics."""
    from belvedere.description.urdf import RobotModel
    from belvedere.sim.physics import PhysicsSimulation, save_world
    from belvedere.world import read_world

    xacro = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    sim = PhysicsSimulation(graph)
    for i, y in ((1, 0.0), (2, 1.5)):
        model = RobotModel.from_path(xacro)
        sim.spawn(
            model,
            name=f"robot_{i}",
            pose=Pose((0.0, y, 0.0)),
            packages=packages,
            robot_namespace=f"/robot_{i}/",
        )
    written = save_world(sim, tmp_path / "two.world")
    graph.shutdown()
    again = Graph()
    PhysicsSimulation(again, read_world(written, packages=packages))
    for i in (1, 2):
        assert f"/robot_{i}/scan" in again.topics
    assert "/scan" not in again.topics
    again.shutdown()
