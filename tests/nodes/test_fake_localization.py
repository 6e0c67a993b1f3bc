"""fake_localization as rbx1's fake_amcl.launch runs it beside the fake TurtleBot (ArbotiX's
simulated base): the odometry taken as ground truth gives ``amcl_pose``, a one-pose
``particlecloud`` and TF map → odom; ``delta_*`` place the map, ``initialpose`` shifts it."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.graph import NS, Graph
from belvedere.launch import LaunchError, load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.nodes.amcl import pose_message
from belvedere.packages import PackageIndex
from belvedere.tf import TFBuffer, TransformListener
from tests.conftest import EXAMPLES

FAKE_AMCL = """<launch>
  <include file="$(find rbx1_bringup)/launch/fake_turtlebot.launch"/>
  <node name="fake_localization" pkg="fake_localization" type="fake_localization"
        clear_params="true" output="screen">
    <remap from="base_pose_ground_truth" to="odom"/>
    <param name="global_frame_id" value="map"/>
    <param name="base_frame_id" value="base_footprint"/>
    {extra}
  </node>
</launch>
"""


def _start(tmp_path: Path, extra: str = "") -> Graph:
    launch = tmp_path / "fake_amcl.launch"
    launch.write_text(FAKE_AMCL.format(extra=extra))
    packages = PackageIndex.from_environment(package_path=[EXAMPLES])
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    return graph


def _yaw(q: Any) -> float:
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def _drive(graph: Graph) -> tuple[list[Any], list[Any], list[Any], TFBuffer]:
    probe = graph.create_node("probe")
    poses: list[Any] = []
    clouds: list[Any] = []
    odom: list[Any] = []
    probe.subscribe("/amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", poses.append)
    probe.subscribe("/particlecloud", "geometry_msgs/PoseArray", clouds.append)
    probe.subscribe("/odom", "nav_msgs/Odometry", odom.append)
    buffer = TFBuffer()
    TransformListener(probe, buffer)
    cmd = probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    cmd.publish_data({"linear": {"x": 0.2}, "angular": {"z": 0.3}})
    graph.run(duration=3.0)
    return poses, clouds, odom, buffer


def test_the_odometry_is_the_pose_in_the_map(tmp_path: Path) -> None:
    graph = _start(tmp_path)
    poses, clouds, odom, buffer = _drive(graph)
    assert len(poses) > 10
    last = poses[-1]
    assert last.header.frame_id == "map"
    stamp = last.header.stamp.sec * NS + last.header.stamp.nanosec
    truth = next(m for m in odom if m.header.stamp.sec * NS + m.header.stamp.nanosec == stamp)
    assert last.pose.pose.position.x == pytest.approx(truth.pose.pose.position.x)
    assert last.pose.pose.position.y == pytest.approx(truth.pose.pose.position.y)
    assert list(last.pose.covariance) == [0.0] * 36
    assert len(clouds[-1].poses) == 1
    assert clouds[-1].poses[0] == last.pose.pose
    # map → odom is the identity, stamped transform_tolerance (0.1 s) ahead of the odometry
    t = buffer.lookup_transform("map", "odom", 0)
    assert t.translation == pytest.approx((0.0, 0.0, 0.0), abs=1e-9)
    assert buffer.lookup_transform("map", "base_footprint", stamp).translation[0] == pytest.approx(
        truth.pose.pose.position.x
    )


def test_delta_places_the_map_and_initialpose_shifts_it(tmp_path: Path) -> None:
    extra = (
        '<param name="delta_x" value="1.0"/><param name="delta_y" value="-2.0"/>'
        '<param name="delta_yaw" value="0.5"/>'
    )
    graph = _start(tmp_path, extra)
    poses, _, odom, buffer = _drive(graph)
    last = poses[-1]
    stamp = last.header.stamp.sec * NS + last.header.stamp.nanosec
    truth = next(m for m in odom if m.header.stamp.sec * NS + m.header.stamp.nanosec == stamp)
    # fake_localization's offset: turned by -delta_yaw, then moved by (-delta_x, -delta_y)
    tx, ty = truth.pose.pose.position.x, truth.pose.pose.position.y
    c, s = math.cos(-0.5), math.sin(-0.5)
    shifted = (c * tx - s * ty - 1.0, s * tx + c * ty + 2.0)
    assert (last.pose.pose.position.x, last.pose.pose.position.y) == pytest.approx(shifted)
    assert _yaw(last.pose.pose.orientation) == pytest.approx(
        math.remainder(_yaw(truth.pose.pose.orientation) - 0.5, math.tau)
    )
    # a pose estimate moves the map so that the robot is there now
    probe = graph.create_node("setter")
    pub = probe.publisher("/initialpose", "geometry_msgs/PoseWithCovarianceStamped")
    now = graph.now_ns()
    pub.publish(pose_message("map", now, np.array([5.0, 5.0, 1.0]), [0.0] * 36))
    graph.run(duration=0.5)
    after = buffer.lookup_transform("map", "base_footprint", 0)
    moved = math.hypot(after.translation[0] - 5.0, after.translation[1] - 5.0)
    assert moved < 0.2  # where it was put, plus half a second of driving


def test_a_bad_parameter_stops_the_launch(tmp_path: Path) -> None:
    with pytest.raises(LaunchError) as caught:
        _start(tmp_path, '<param name="delta_x" value="east"/>')
    assert "/fake_localization: parameter delta_x: expected a number, got 'east'" in (
        caught.value.describe()
    )
