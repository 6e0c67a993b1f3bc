"""The live nodes that read scans and odometry — slam_gmapping, hector_mapping, amcl and a
costmap — fed hostile messages on the graph (simulated time): each kind of bad reading is
one counted warning naming the node, never a traceback, and the node goes on with the good
readings after it."""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest

from belvedere.bounded import GRID_CELLS
from belvedere.graph import Graph, Node
from belvedere.maps import OccupancyMap, grid_message
from belvedere.msgs import build, types
from belvedere.nodes._costmap import Costmap2DROS
from belvedere.nodes.amcl import pose_message
from belvedere.tf import TFBuffer
from tests.nav import hostile
from tests.nav.hostile import Pose

Spoil = Callable[[int, Pose, Any], tuple[Pose, Any]]


@pytest.fixture
def warnings(caplog: pytest.LogCaptureFixture) -> Iterator[pytest.LogCaptureFixture]:
    with caplog.at_level(logging.WARNING, logger="belvedere"):
        yield caplog


def _lines(caplog: pytest.LogCaptureFixture) -> list[str]:
    return [r.getMessage() for r in caplog.records]


def _no_tracebacks(caplog: pytest.LogCaptureFixture) -> None:
    failed = [r.getMessage() for r in caplog.records if r.exc_info or "failed" in r.getMessage()]
    assert failed == []


def _drive(graph: Graph, count: int, spoil: Spoil | None = None, *, start: int = 0) -> None:
    """``count`` scans along :func:`hostile.path`, 10 a second: odom → base_link on /tf,
    then the scan; ``spoil`` may replace either."""
    probe = graph.create_node(f"driver_{start}")
    tf_pub = probe.publisher("/tf", "tf2_msgs/TFMessage", queue_size=100)
    scan_pub = probe.publisher("/scan", "sensor_msgs/LaserScan", queue_size=100)
    for i, pose in enumerate(hostile.path(start + count)[start:], start=start):
        stamp = probe.now_ns()
        msg = hostile.scan(stamp, hostile.room_ranges(pose))
        if spoil is not None:
            pose, msg = spoil(i, pose, msg)
        tf_pub.publish(hostile.tf("odom", "base_link", pose, stamp))
        scan_pub.publish(msg)
        graph.run(duration=0.1)


def _graph() -> Graph:
    graph = Graph()
    driver = graph.create_node("mount")
    static = driver.publisher("/tf_static", "tf2_msgs/TFMessage", latch=True)
    static.publish(hostile.mount(0))
    return graph


def _node(graph: Graph, name: str, params: dict[str, Any]) -> Node:
    node = graph.create_node(name)
    for key, value in params.items():
        node.set_param(f"~{key}", value)
    return node


def _hostile_scans(i: int, pose: Pose, msg: Any) -> tuple[Pose, Any]:
    """Scans 3-6 spoiled: NaN angle_increment, 70,000 beams, a third of the ranges NaN, a
    1e7 m range with range_max 1e30."""
    stamp = msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
    if i == 3:
        return pose, hostile.scan(stamp, msg.ranges, increment=math.nan)
    if i == 4:
        return pose, hostile.scan(stamp, np.full(70_000, 3.0))
    if i == 5:
        ranges = np.array(msg.ranges)
        ranges[::3] = np.nan
        return pose, hostile.scan(stamp, ranges)
    if i == 6:
        ranges = np.array(msg.ranges)
        ranges[7] = 1e7
        return pose, hostile.scan(stamp, ranges, range_max=1e30)
    return pose, msg


def _hostile_odometry(i: int, pose: Pose, msg: Any) -> tuple[Pose, Any]:
    """Odometry of scans 10-12 spoiled: a jump to 1e7 m and back, +inf, 1e12 m."""
    x, y, yaw = pose
    if i == 10:
        return (1e7, y, yaw), msg
    if i == 11:
        return (math.inf, y, yaw), msg
    if i == 12:
        return (x, 1e12, yaw), msg
    return pose, msg


def _both(i: int, pose: Pose, msg: Any) -> tuple[Pose, Any]:
    return _hostile_odometry(i, *_hostile_scans(i, pose, msg))


def test_slam_gmapping_skips_bad_scans_and_odometry_and_goes_on(
    warnings: pytest.LogCaptureFixture,
) -> None:
    from belvedere.nodes.gmapping import _GMappingNode

    graph = _graph()
    params = {"base_frame": "base_link", "xmin": -10, "xmax": 10, "ymin": -10, "ymax": 10}
    params |= {"map_update_interval": 0.5, "linearUpdate": 0.25}
    node = _GMappingNode(_node(graph, "slam_gmapping", params))
    maps: list[Any] = []
    graph.create_node("probe").subscribe("/map", "nav_msgs/OccupancyGrid", maps.append)

    def first_is_bad(i: int, pose: Pose, msg: Any) -> tuple[Pose, Any]:
        if i == 0:  # the laser's geometry comes from the first good scan
            stamp = msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
            return pose, hostile.scan(stamp, msg.ranges, angle_min=math.inf)
        return _both(i, pose, msg)

    _drive(graph, 30, first_is_bad)
    lines = _lines(warnings)
    expected = [
        "/slam_gmapping: skipped 1 scan: their angle_min is not finite "
        "(the first at 0.000 s: angle_min inf)",
        "/slam_gmapping: skipped 1 scan: their angle_increment is not finite "
        "(the first at 0.300 s: angle_increment nan)",
        "/slam_gmapping: skipped 1 scan: more than 65,536 beams "
        "(the first at 0.400 s: 70,000 beams)",
        "/slam_gmapping: dropped 120 NaN ranges in 1 scan",
        "/slam_gmapping: left 1 scan out of the map: a grid would grow past the cap of "
        "33,554,432 cells (the first at 1.000 s: submap 0's grid to 546,644,566,071,968 cells)",
        "/slam_gmapping: skipped 1 scan: their odometry pose is not finite "
        "(the first at 1.100 s: (inf, 0.486065, 0.165))",
        "/slam_gmapping: skipped 1 scan: their odometry pose is more than 1e+08 m from the "
        "origin (the first at 1.200 s: (-1.4, 1e+12, 0.18))",
    ]
    assert lines == expected
    _no_tracebacks(warnings)
    core = node.core
    assert core.slam is not None
    assert len(core.processed) == 30 - 5  # the angle_min, nan, 70,000 beams, inf and 1e12
    last = maps[-1]
    assert last.header.stamp.sec * 10**9 + last.header.stamp.nanosec > 2 * 10**9
    assert (last.info.width, last.info.height) == (400, 400)  # the 1e7 m range is no hit
    data = np.asarray(last.data).reshape(400, 400)
    assert (data == 100).sum() > 100  # the room's walls
    assert np.isfinite(core.map_to_odom()).all()


def test_slam_gmapping_clips_range_max_to_what_a_grid_holds(
    warnings: pytest.LogCaptureFixture,
) -> None:
    from belvedere.nodes.gmapping import _GMappingNode

    graph = _graph()
    node = _GMappingNode(_node(graph, "slam_gmapping", {"base_frame": "base_link"}))

    def far(i: int, pose: Pose, msg: Any) -> tuple[Pose, Any]:
        stamp = msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
        ranges = np.array(msg.ranges)
        ranges[::40] = 1e7  # finite, and beyond what any grid can hold
        return pose, hostile.scan(stamp, ranges, range_max=1e30)

    _drive(graph, 12, far)
    assert _lines(warnings) == [
        "/slam_gmapping: uses ranges up to 144 m, the most a grid of 33,554,432 cells at "
        "0.05 m holds around the laser (its range_max is 1e+30 m)"
    ]
    grid = node.core.occupancy()
    assert grid is not None
    assert grid.data.shape == (4000, 4000)  # xmin..xmax: not grown for the 1e7 m ranges
    assert (grid.data == 100).sum() > 100


def test_hector_mapping_skips_bad_scans_and_goes_on(warnings: pytest.LogCaptureFixture) -> None:
    from belvedere.nodes.hector_mapping import _HectorNode

    graph = _graph()
    params = {"base_frame": "base_link", "map_size": 512, "map_resolution": 0.05}
    _HectorNode(_node(graph, "hector_mapping", params))
    poses: list[Any] = []
    graph.create_node("probe").subscribe(
        "/slam_out_pose", "geometry_msgs/PoseStamped", poses.append
    )

    _drive(graph, 20, _hostile_scans)
    assert _lines(warnings) == [
        "/hector_mapping: skipped 1 scan: their angle_increment is not finite "
        "(the first at 0.300 s: angle_increment nan)",
        "/hector_mapping: skipped 1 scan: more than 65,536 beams "
        "(the first at 0.400 s: 70,000 beams)",
        "/hector_mapping: dropped 120 NaN ranges in 1 scan",
    ]
    _no_tracebacks(warnings)
    assert len(poses) == 20 - 2
    last = poses[-1].pose.position
    assert math.isfinite(last.x)
    assert math.isfinite(last.y)


def _room_map() -> OccupancyMap:
    size = 220  # 11 m at 5 cm, the room's walls inside
    data = np.zeros((size, size), dtype=np.int8)
    wall = round(0.5 / 0.05)
    data[wall, wall:-wall] = data[-wall - 1, wall:-wall] = 100
    data[wall:-wall, wall] = data[wall:-wall, -wall - 1] = 100
    return OccupancyMap(data, 0.05, (-5.5, -5.5, 0.0))


def test_amcl_skips_bad_scans_poses_and_maps_and_goes_on(
    warnings: pytest.LogCaptureFixture,
) -> None:
    from belvedere.nodes.amcl import _AmclNode

    graph = _graph()
    start = hostile.path(1)[0]
    params = {
        "use_map_topic": True,
        "base_frame_id": "base_link",
        "initial_pose_x": start[0],
        "initial_pose_y": start[1],
        "update_min_d": 0.0,
        "update_min_a": 0.0,
        "min_particles": 100,
        "max_particles": 300,
    }
    _AmclNode(_node(graph, "amcl", params))
    probe = graph.create_node("probe")
    poses: list[Any] = []
    probe.subscribe("/amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", poses.append)
    map_pub = probe.publisher("/map", "nav_msgs/OccupancyGrid", latch=True)
    map_pub.publish(grid_message(_room_map(), frame_id="map", stamp_ns=0))
    graph.run(duration=0.1)
    # (a finite jump, 1e7 m and back, amcl takes as motion, as ROS's does: it is left out)
    _drive(graph, 20, lambda i, pose, msg: _both(i, pose, msg) if i != 10 else (pose, msg))
    # a bad initial pose and a map too big to hold
    initial = probe.publisher("/initialpose", "geometry_msgs/PoseWithCovarianceStamped")
    initial.publish(pose_message("map", probe.now_ns(), np.array([math.nan, 0.0, 0.0]), [0.0] * 36))
    huge = types().cls("nav_msgs/OccupancyGrid")(
        build.header(0, "map"),
        types().cls("nav_msgs/MapMetaData")(
            build.stamp(0), 0.05, 6000, 6000, grid_message(_room_map(), frame_id="map").info.origin
        ),
        np.zeros(0, dtype=np.int8),
    )
    map_pub.publish(huge)
    _drive(graph, 5, start=20)
    lines = _lines(warnings)
    assert lines == [
        "/amcl: skipped 1 scan: their angle_increment is not finite "
        "(the first at 0.400 s: angle_increment nan)",
        "/amcl: skipped 1 scan: more than 65,536 beams (the first at 0.500 s: 70,000 beams)",
        "/amcl: dropped 120 NaN ranges in 1 scan",
        "/amcl: skipped 1 scan: their odometry pose is not finite "
        "(the first at 1.200 s: (inf, 0.486065, 0.165))",
        "/amcl: skipped 1 scan: their odometry pose is more than 1e+08 m from the origin "
        "(the first at 1.300 s: (-1.4, 1e+12, 0.18))",
        "/amcl: ignored 1 initial pose: it is not finite (the first at 2.100 s: (nan, 0, 0))",
        "/amcl: map refused: 6,000 x 6,000 cells, more than the cap of 33,554,432",
    ]
    _no_tracebacks(warnings)
    last = poses[-1]
    assert last.header.stamp.sec * 10**9 + last.header.stamp.nanosec > 2 * 10**9
    p = last.pose.pose.position
    truth = hostile.path(25)[-1]
    assert math.hypot(p.x - truth[0], p.y - truth[1]) < 0.5


def test_a_costmap_skips_bad_readings_and_poses_and_goes_on(
    warnings: pytest.LogCaptureFixture,
) -> None:
    graph = _graph()
    params = {
        "global_frame": "odom",
        "robot_base_frame": "base_link",
        "rolling_window": True,
        "width": 12.0,
        "height": 12.0,
        "obstacle_range": 6.0,
        "update_frequency": 0.0,
        "publish_frequency": 0.0,
        "transform_tolerance": 10.0,
        "robot_radius": 0.2,
        "observation_sources": "scan",
        "scan": {"data_type": "LaserScan", "topic": "/scan", "marking": True, "clearing": True},
        "raytrace_range": 1e30,
    }
    node = graph.create_node("move_base")
    for key, value in params.items():
        node.set_param(f"~local_costmap/{key}", value)
    buffer = TFBuffer()
    node.subscribe("/tf", "tf2_msgs/TFMessage", buffer.set_message)
    node.subscribe("/tf_static", "tf2_msgs/TFMessage", lambda m: buffer.set_message(m, static=True))
    costmap = Costmap2DROS(node, "local_costmap", buffer)
    updated: list[bool] = []

    def update_too(i: int, pose: Pose, msg: Any) -> tuple[Pose, Any]:
        if i > 0:  # (TF has the robot's pose from the first scan on)
            updated.append(costmap.update_now())
        return _both(i, pose, msg)

    _drive(graph, 20, update_too)
    assert _lines(warnings) == [
        "/move_base/local_costmap: skipped 1 scan from scan: their angle_increment is not "
        "finite (the first at 0.300 s: angle_increment nan)",
        "/move_base/local_costmap: skipped 1 scan from scan: more than 65,536 beams "
        "(the first at 0.400 s: 70,000 beams)",
        "/move_base/local_costmap: dropped 120 NaN ranges in 1 scan from scan",
        "/move_base/local_costmap: dropped 1 reading from scan: the sensor's pose is not "
        "finite (the first at 1.100 s: (nan, nan, nan))",
        "/move_base/local_costmap: no robot pose for 1 update: it is not finite "
        "(the first at 1.200 s: (nan, nan, 0.165))",
        "/move_base/local_costmap: dropped 1 reading from scan: the sensor's pose is more "
        "than 1e+08 m from the origin (the first at 1.200 s: (-1.30162, 1e+12, 0.2))",
        "/move_base/local_costmap: no robot pose for 1 update: it is more than 1e+08 m from "
        "the origin (the first at 1.300 s: (-1.4, 1e+12, 0.18))",
    ]
    _no_tracebacks(warnings)
    assert costmap.update_now()
    grid = costmap.grid()
    assert grid.costs.shape == (240, 240)
    assert (grid.costs == 254).sum() > 10  # the walls the good scans saw
    assert grid.costs.size < GRID_CELLS
