"""amcl on a running graph: the physics simulation of the mbot in the cloister, map_server
serving the cloister's map, and amcl localizing the robot as it drives; its topics, TF,
services, saved pose, and the one error a bad parameter gives."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.graph import NS, Graph
from belvedere.launch import LaunchError, load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.maps import grid_message, save_map
from belvedere.msgs import types
from belvedere.nodes.amcl import base_bearings, pose_message
from belvedere.packages import PackageIndex
from belvedere.tf import Transform, quat_xyzw_from_rpy
from tests.conftest import EXAMPLES
from tests.nav import simulated

SIM = """
    <include file="$(find gazebo_ros)/launch/empty_world.launch">
        <arg name="world_name" value="$(find mbot_gazebo)/worlds/cloister.world"/>
        <arg name="use_sim_time" value="true"/>
        <arg name="gui" value="false"/>
    </include>
    <param name="robot_description" command="$(find xacro)/xacro --inorder
      '$(find mbot_description)/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro'"/>
    <node name="joint_state_publisher" pkg="joint_state_publisher" type="joint_state_publisher"/>
    <node name="robot_state_publisher" pkg="robot_state_publisher" type="robot_state_publisher"/>
    <node name="urdf_spawner" pkg="gazebo_ros" type="spawn_model"
          args="-urdf -model mrobot -param robot_description -x 0 -y -4.5"/>
"""

MAP_SERVER = """
    <node pkg="map_server" type="map_server" name="map_server"
          args="$(find loc_pkg)/maps/cloister.yaml"/>
"""

AMCL_NODE = """
    <node pkg="amcl" type="amcl" name="amcl">
        <param name="base_frame_id" value="base_footprint"/>
        <param name="initial_pose_y" value="-4.5"/>
        <param name="laser_model_type" value="likelihood_field_prob"/>
        <param name="min_particles" value="300"/>
        <param name="max_particles" value="1000"/>
        <param name="update_min_d" value="0.1"/>
        <param name="save_pose_rate" value="1.0"/>
        {extra}
    </node>
"""

AMCL = MAP_SERVER + AMCL_NODE


@pytest.fixture(scope="module")
def pkg(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A package ``loc_pkg`` with the cloister's map in ``maps/``."""
    root = tmp_path_factory.mktemp("ws") / "loc_pkg"
    (root / "maps").mkdir(parents=True)
    (root / "launch").mkdir()
    (root / "package.xml").write_text("<package><name>loc_pkg</name></package>")
    save_map(root / "maps" / "cloister", simulated.world_map())
    return root


def _start(pkg: Path, body: str, name: str = "loc.launch") -> Graph:
    launch = pkg / "launch" / name
    launch.write_text(f"<launch>{body}</launch>\n")
    packages = PackageIndex.from_environment(
        package_path=[pkg.parent], near=EXAMPLES / "mbot_navigation/launch/gmapping_demo.launch"
    )
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    return graph


def _yaw(q: Any) -> float:
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def test_amcl_localizes_the_driving_robot_and_answers_its_services(pkg: Path) -> None:
    graph = _start(pkg, SIM + AMCL.format(extra=""))
    probe = graph.create_node("probe")
    poses: list[Any] = []
    clouds: list[Any] = []
    truth: list[Any] = []
    map_odom: list[Any] = []
    scans: list[int] = []

    def on_tf(msg: Any) -> None:
        for t in msg.transforms:
            pair = (t.header.frame_id, t.child_frame_id)
            if pair == ("map", "odom"):
                map_odom.append(t)
            elif pair == ("odom", "base_footprint"):
                truth.append(t)

    probe.subscribe("/amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", poses.append)
    probe.subscribe("/particlecloud", "geometry_msgs/PoseArray", clouds.append)
    probe.subscribe("/tf", "tf2_msgs/TFMessage", on_tf, queue_size=100)
    probe.subscribe(
        "/scan",
        "sensor_msgs/LaserScan",
        lambda m: scans.append(m.header.stamp.sec * NS + m.header.stamp.nanosec),
    )
    cmd = probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    cmd.publish_data({"linear": {"x": 0.3}})
    graph.run(duration=8.0)

    assert len(poses) >= 5
    last = poses[-1]
    assert last.header.frame_id == "map"
    stamp = last.header.stamp.sec * NS + last.header.stamp.nanosec
    assert stamp in scans  # stamped with the scan it came from
    # the physics' odometry is the true pose: amcl agrees with it
    true = next(
        t for t in truth if t.header.stamp.sec * NS + t.header.stamp.nanosec >= stamp
    ).transform
    p = last.pose.pose
    assert math.hypot(p.position.x - true.translation.x, p.position.y - true.translation.y) < 0.08
    assert abs(math.remainder(_yaw(p.orientation) - _yaw(true.rotation), math.tau)) < 0.05
    cov = np.asarray(last.pose.covariance).reshape(6, 6)
    assert 0 < cov[0, 0] < 0.05
    assert 0 < cov[1, 1] < 0.05
    assert 0 < cov[5, 5] < 0.05
    assert cov[2, 2] == cov[3, 3] == cov[4, 4] == 0.0
    # the cloud after each filter update, KLD-sized between min and max
    assert clouds
    assert clouds[-1].header.frame_id == "map"
    assert 300 <= len(clouds[-1].poses) <= 1000
    # map → odom on every scan once localized, transform_tolerance (0.1 s) ahead of it
    assert len(map_odom) >= len(poses)
    ahead = [t.header.stamp.sec * NS + t.header.stamp.nanosec - round(0.1 * NS) for t in map_odom]
    assert set(ahead) <= set(scans)
    # the pose saved to the parameter server (save_pose_rate 1 Hz)
    saved_x = graph.params.get("/amcl/initial_pose_x")
    assert saved_x != 0.0
    assert abs(saved_x - p.position.x) < 0.5
    # with the covariance amcl last published then
    assert graph.params.get("/amcl/initial_cov_xx") in {m.pose.covariance[0] for m in poses}
    assert graph.params.get("/amcl/initial_cov_aa") in {m.pose.covariance[35] for m in poses}

    # global_localization: the next cloud is max_particles spread over the map
    probe.call_service("/global_localization", "std_srvs/Empty")
    count = len(clouds)
    graph.run(duration=0.5)
    spread = np.array([[q.position.x, q.position.y] for q in clouds[count].poses])
    assert len(spread) == 1000
    assert np.ptp(spread[:, 0]) > 10.0
    assert np.ptp(spread[:, 1]) > 8.0

    # set_map: the same map and a pose, which the filter starts from
    cmd.publish_data({})
    request = types().cls("nav_msgs/srv/SetMap_Request")(
        grid_message(simulated.world_map(), frame_id="map"),
        pose_message("map", 0, np.array([2.0, -4.5, 0.0]), [0.01] * 36),
    )
    response = probe.call_service("/set_map", "nav_msgs/SetMap", request)
    assert response.success
    count = len(clouds)
    probe.call_service("/request_nomotion_update", "std_srvs/Empty")
    graph.run(duration=0.5)
    assert len(clouds) > count  # the filter took a scan though the robot stands still
    assert len(clouds[count].poses) == 1000


def test_the_map_topic_initial_poses_and_no_tf(pkg: Path) -> None:
    extra = (
        '<param name="use_map_topic" value="true"/><param name="first_map_only" value="true"/>'
        '<param name="tf_broadcast" value="false"/>'
    )
    graph = _start(pkg, SIM + AMCL.format(extra=extra), "topic.launch")
    probe = graph.create_node("probe")
    poses: list[Any] = []
    map_odom: list[Any] = []

    def on_tf(msg: Any) -> None:
        map_odom.extend(t for t in msg.transforms if t.header.frame_id == "map")

    probe.subscribe("/amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", poses.append)
    probe.subscribe("/tf", "tf2_msgs/TFMessage", on_tf, queue_size=100)
    initial = probe.publisher("/initialpose", "geometry_msgs/PoseWithCovarianceStamped")
    graph.run(duration=1.0)
    assert poses  # the map came on the topic
    assert poses[-1].pose.pose.position.y == pytest.approx(-4.5, abs=0.1)
    cov = [0.0] * 36
    cov[0] = cov[7] = 0.0025
    cov[35] = 0.001
    # a pose in another frame is ignored; one in the map frame restarts the filter there
    initial.publish(pose_message("odom", graph.now_ns(), np.array([1.0, -4.0, 0.0]), cov))
    count = len(poses)
    probe.call_service("/request_nomotion_update", "std_srvs/Empty")
    graph.run(duration=0.5)
    assert poses[-1].pose.pose.position.x < 0.5  # not moved to x = 1
    initial.publish(pose_message("map", graph.now_ns(), np.array([1.0, -4.0, 0.0]), cov))
    count = len(poses)
    graph.run(duration=0.5)
    assert len(poses) > count  # published on the first scan after a new pose
    moved = poses[count].pose.pose.position
    assert (moved.x, moved.y) == pytest.approx((1.0, -4.0), abs=0.15)
    assert not map_odom  # tf_broadcast false


def test_gui_publish_rate_limits_the_particle_cloud(pkg: Path) -> None:
    extra = (
        '<param name="gui_publish_rate" value="1.0"/><param name="resample_interval" value="1"/>'
    )
    graph = _start(pkg, SIM + AMCL.format(extra=extra), "gui.launch")
    probe = graph.create_node("probe")
    poses: list[Any] = []
    clouds: list[Any] = []
    probe.subscribe("/amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", poses.append)
    probe.subscribe("/particlecloud", "geometry_msgs/PoseArray", clouds.append)
    probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True).publish_data(
        {"linear": {"x": 0.4}}
    )
    graph.run(duration=4.0)
    assert len(poses) >= 8  # the filter updated every 0.1 m
    stamps = [m.header.stamp.sec + m.header.stamp.nanosec / NS for m in clouds]
    assert 2 <= len(stamps) <= 5
    assert min(np.diff(stamps)) >= 1.0  # at most one a second


def test_amcl_started_before_the_map_server_asks_again(
    pkg: Path, caplog: pytest.LogCaptureFixture
) -> None:
    body = SIM + AMCL_NODE.format(extra="") + MAP_SERVER  # amcl first
    graph = _start(pkg, body, "late_map.launch")
    probe = graph.create_node("probe")
    poses: list[Any] = []
    probe.subscribe("/amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", poses.append)
    graph.run(duration=1.5)
    assert "Request for map failed; trying again..." in caplog.text
    assert poses  # the map came on a later request


@pytest.mark.parametrize(
    ("param", "value", "expected"),
    [
        (
            "laser_model_type",
            "beams",
            "parameter laser_model_type: expected one of likelihood_field, beam, "
            "likelihood_field_prob, got 'beams'",
        ),
        (
            "odom_model_type",
            "ackermann",
            "parameter odom_model_type: expected one of diff, omni, diff-corrected, "
            "omni-corrected, got 'ackermann'",
        ),
        (
            "max_particles",
            "50",
            "parameter max_particles: expected at least min_particles (100), got 50",
        ),
        ("kld_err", "fine", "parameter kld_err: expected a number, got 'fine'"),
    ],
)
def test_a_bad_parameter_stops_the_launch(pkg: Path, param: str, value: str, expected: str) -> None:
    body = (
        '\n  <node pkg="amcl" type="amcl" name="amcl">\n'
        f'    <param name="{param}" value="{value}"/>\n  </node>\n'
    )
    with pytest.raises(LaunchError) as caught:
        _start(pkg, body, "bad.launch")
    launch = pkg / "launch" / "bad.launch"
    assert caught.value.describe() == f"{launch}:2:3: error: /amcl: {expected}"


@pytest.mark.parametrize(
    ("rpy", "first", "increment"),
    [
        ((0.0, 0.0, 0.0), -1.0, 0.01),
        ((0.0, 0.0, 0.5), -0.5, 0.01),  # turned on the base
        ((math.pi, 0.0, 0.0), 1.0, -0.01),  # upside down: the beams run the other way
    ],
)
def test_the_scans_bearings_in_the_base_frame(
    rpy: tuple[float, float, float], first: float, increment: float
) -> None:
    mount = Transform((0.1, 0.0, 0.2), quat_xyzw_from_rpy(*rpy))
    got = base_bearings(mount, -1.0, 0.01)
    assert got == pytest.approx((first, increment))


def _amcl_poses(pkg: Path, seed: int) -> list[tuple[float, float, float]]:
    launch = pkg / "launch" / "seeded.launch"
    launch.write_text(f"<launch>{SIM}{AMCL.format(extra='')}</launch>\n")
    packages = PackageIndex.from_environment(
        package_path=[pkg.parent], near=EXAMPLES / "mbot_navigation/launch/gmapping_demo.launch"
    )
    graph = Graph(seed=seed)
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    probe = graph.create_node("probe")
    poses: list[Any] = []
    probe.subscribe("/amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", poses.append)
    probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True).publish_data(
        {"linear": {"x": 0.3}, "angular": {"z": 0.2}}
    )
    graph.run(duration=3.0)
    return [(m.pose.pose.position.x, m.pose.pose.position.y, m.pose.covariance[0]) for m in poses]


def test_the_graphs_seed_makes_amcl_repeat_itself(pkg: Path) -> None:
    a, b, c = _amcl_poses(pkg, 11), _amcl_poses(pkg, 11), _amcl_poses(pkg, 12)
    assert len(a) > 3
    assert a == b
    assert a != c
