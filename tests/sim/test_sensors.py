"""Sensors in the physics engine: a laser in a box room, a camera and a Kinect, an IMU,
ground truth odometry."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import LaserSensor, PhysicsSimulation
from belvedere.world import read_world, read_world_string
from tests.conftest import EXAMPLES

XACRO = EXAMPLES / "mbot_description/urdf/xacro/gazebo"
BOX_ROOM = EXAMPLES / "mbot_gazebo/worlds/box_room.world"
EMPTY = EXAMPLES / "mbot_gazebo/worlds/empty.world"


def _model(name: str, **replace: str) -> RobotModel:
    urdf = RobotModel.from_path(XACRO / name).to_urdf()
    for old, new in replace.items():
        assert old in urdf, old
        urdf = urdf.replace(old, new)
    return RobotModel.from_string(urdf, path=name)


def _expected_range(angle: float) -> float:
    """Distance from the room's centre to its inner walls (x = +-2, y = +-1.5)."""
    c, s = abs(math.cos(angle)), abs(math.sin(angle))
    return min(2.0 / c if c > 1e-12 else math.inf, 1.5 / s if s > 1e-12 else math.inf)


def _scans(model: RobotModel, world: Any, seconds: float) -> list[Any]:
    graph = Graph()
    sim = PhysicsSimulation(graph, world)
    sim.spawn(model, name="mbot")
    scans: list[Any] = []
    graph.create_node("probe").subscribe("/scan", "sensor_msgs/LaserScan", scans.append)
    graph.run(duration=seconds)
    return scans


def test_laser_ranges_equal_the_room_within_a_centimetre() -> None:
    model = _model(
        "mbot_with_laser_gazebo.xacro", **{"<stddev>0.01</stddev>": "<stddev>0</stddev>"}
    )
    scans = _scans(model, read_world(BOX_ROOM), 2.0)
    assert len(scans) == 11  # update_rate 5.5 Hz
    scan = scans[-1]
    assert (scan.header.frame_id, len(scan.ranges)) == ("laser_link", 360)
    assert scan.angle_min == -3.0
    assert scan.angle_increment == pytest.approx(6.0 / 359)
    assert (scan.range_min, scan.range_max) == (pytest.approx(0.1), pytest.approx(6.0))
    angles = scan.angle_min + scan.angle_increment * np.arange(360)
    expected = np.array([_expected_range(a) for a in angles])
    assert np.max(np.abs(scan.ranges - expected)) < 0.01


def test_laser_beyond_range_is_inf_and_noise_is_seeded() -> None:
    model = _model("mbot_with_laser_gazebo.xacro", **{"<max>6.0</max>": "<max>1.8</max>"})
    scan = _scans(model, read_world(BOX_ROOM), 0.5)[-1]
    angles = scan.angle_min + scan.angle_increment * np.arange(360)
    expected = np.array([_expected_range(a) for a in angles])
    assert np.all(np.isposinf(scan.ranges[expected > 1.81]))
    near = expected < 1.75
    errors = scan.ranges[near] - expected[near]
    assert 0.005 < float(np.std(errors)) < 0.015  # stddev 0.01
    again = _scans(model, read_world(BOX_ROOM), 0.5)[-1]
    assert np.array_equal(scan.ranges, again.ranges)  # the same seed, the same noise


def test_laser_costs_nothing_without_subscribers() -> None:
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world(BOX_ROOM))
    robot = sim.spawn(_model("mbot_with_laser_gazebo.xacro"), name="mbot")
    laser = next(p for p in robot.plugins if isinstance(p, LaserSensor))
    graph.run(duration=1.0)
    assert laser.gate.last_ns is None  # never cast a ray


COLOURED_BOX = """<sdf version='1.6'><world name='w'>
  <include><uri>model://ground_plane</uri></include>
  <model name='target'><static>true</static><pose>{x} 0 0.5 0 0 0</pose>
    <link name='l'>
      <collision name='c'><geometry><box><size>0.5 2 1</size></box></geometry></collision>
      <visual name='v'><geometry><box><size>0.5 2 1</size></box></geometry>
        <material><diffuse>0 0.9 0 1</diffuse></material></visual>
    </link></model>
</world></sdf>"""


def test_camera_sees_a_coloured_box() -> None:
    graph = Graph()
    world = read_world_string(COLOURED_BOX.format(x=2.0))
    sim = PhysicsSimulation(graph, world)
    sim.spawn(_model("mbot_with_camera_gazebo.xacro"), name="mbot")
    images: list[Any] = []
    infos: list[Any] = []
    probe = graph.create_node("probe")
    probe.subscribe("/camera/image_raw", "sensor_msgs/Image", images.append)
    probe.subscribe("/camera/camera_info", "sensor_msgs/CameraInfo", infos.append)
    graph.run(duration=0.5)
    assert images, "no image (is EGL rendering available?)"
    image = images[-1]
    assert (image.encoding, image.width, image.height) == (
        "rgb8",
        infos[-1].width,
        infos[-1].height,
    )
    pixels = np.asarray(image.data).reshape(image.height, image.width, 3)
    centre = pixels[image.height // 2, image.width // 2].astype(int)
    r, g, b = centre
    # The face turned from the sun: only the scene's ambient light (0.4) on diffuse 0.9.
    assert (r, b) == (0, 0), centre
    assert g == pytest.approx(0.4 * 0.9 * 255, rel=0.05), centre
    k = infos[-1].K
    assert k[0] == pytest.approx(image.width / (2 * math.tan(1.3962634 / 2)), rel=1e-3)


def test_kinect_depth_is_the_distance() -> None:
    graph = Graph()
    world = read_world_string(COLOURED_BOX.format(x=1.5))
    sim = PhysicsSimulation(graph, world)
    packages = PackageIndex([EXAMPLES])
    robot = sim.spawn(_model("mbot_with_kinect_gazebo.xacro"), name="mbot", packages=packages)
    depths: list[Any] = []
    clouds: list[Any] = []
    probe = graph.create_node("probe")
    probe.subscribe("/kinect/depth/image_raw", "sensor_msgs/Image", depths.append)
    probe.subscribe("/kinect/depth/points", "sensor_msgs/PointCloud2", clouds.append)
    graph.run(duration=0.3)
    assert depths, "no depth image (is EGL rendering available?)"
    depth = np.asarray(depths[-1].data).view(np.float32).reshape(480, 640)
    camera_x = sim.engine.link_pose(robot.build, "kinect_link")[0, 3]
    expected = 1.5 - 0.25 - camera_x  # the box's near face
    assert float(depth[240, 320]) == pytest.approx(expected, abs=0.01)
    cloud = np.asarray(clouds[-1].data).view(np.float32).reshape(480, 640, 4)
    assert float(cloud[240, 320, 2]) == pytest.approx(expected, abs=0.01)  # optical z


IMU_AND_P3D = """<gazebo>
  <plugin name="imu" filename="libgazebo_ros_imu.so">
    <bodyName>base_link</bodyName><topicName>imu</topicName><updateRate>50</updateRate>
  </plugin>
  <plugin name="truth" filename="libgazebo_ros_p3d.so">
    <bodyName>base_footprint</bodyName><topicName>ground_truth</topicName>
    <frameName>world</frameName><updateRate>50</updateRate>
  </plugin>
</gazebo></robot>"""


def test_imu_and_ground_truth() -> None:
    model = _model("mbot_gazebo.xacro", **{"</robot>": IMU_AND_P3D})
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world(EMPTY))
    sim.spawn(model, name="mbot")
    imu: list[Any] = []
    truth: list[Any] = []
    probe = graph.create_node("probe")
    probe.subscribe("/imu", "sensor_msgs/Imu", imu.append)
    probe.subscribe("/ground_truth", "nav_msgs/Odometry", truth.append)
    graph.run(duration=1.0)
    assert len(imu) == 50
    assert imu[-1].linear_acceleration.z == pytest.approx(9.8, abs=0.05)  # resting: gravity
    assert imu[-1].orientation.w == pytest.approx(1.0, abs=1e-3)
    assert truth[-1].header.frame_id == "world"
    assert truth[-1].child_frame_id == "base_footprint"
    assert truth[-1].pose.pose.position.z == pytest.approx(0.0, abs=2e-3)
