"""Costmap2DROS on a graph: map_server's map and a static TF in a launch, the course's global
costmap parameters, a laser scan marking obstacles, the published costmap with costmap_2d's
value translation, its updates and the footprint."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.graph import Graph, Node
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.maps import OccupancyMap, save_map
from belvedere.msgs import build, types
from belvedere.nav.costmap import LETHAL, NO_INFORMATION
from belvedere.nodes._costmap import COST_TRANSLATION, Costmap2DROS, cloud_points, scan_points
from belvedere.packages import PackageIndex
from belvedere.tf import TFBuffer

PARAMS: dict[str, Any] = {
    "obstacle_range": 2.5,
    "raytrace_range": 3.0,
    "robot_radius": 0.175,
    "inflation_radius": 0.3,
    "max_obstacle_height": 0.6,
    "observation_sources": "scan",
    "scan": {"data_type": "LaserScan", "topic": "/scan", "marking": True, "clearing": True},
    "global_frame": "map",
    "robot_base_frame": "base_footprint",
    "update_frequency": 5.0,
    "publish_frequency": 2.0,
    "static_map": True,
    "rolling_window": False,
    "transform_tolerance": 1.0,
    "map_type": "costmap",
    "track_unknown_space": True,
}


@pytest.fixture
def graph(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Graph:
    """map_server serving a 4 x 3 m room (unknown strip on the right), the robot at (1, 1)
    by a static map → base_footprint and the laser 0.1 m ahead of it."""
    root = tmp_path / "ws" / "nav_pkg"
    (root / "maps").mkdir(parents=True)
    (root / "package.xml").write_text("<package><name>nav_pkg</name></package>")
    data = np.zeros((60, 80), dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 100
    data[:, 70:79] = -1
    monkeypatch.chdir(root / "maps")
    save_map("room", OccupancyMap(data, 0.05, (0.0, 0.0, 0.0)))
    monkeypatch.chdir(tmp_path)
    launch = root / "nav.launch"
    launch.write_text(
        "<launch>\n"
        '  <node pkg="map_server" type="map_server" name="map_server"'
        ' args="$(find nav_pkg)/maps/room.yaml"/>\n'
        '  <node pkg="tf2_ros" type="static_transform_publisher" name="base"'
        ' args="1 1 0 0 0 0 map base_footprint"/>\n'
        '  <node pkg="tf2_ros" type="static_transform_publisher" name="laser"'
        ' args="0.1 0 0.2 0 0 0 base_footprint laser"/>\n'
        "</launch>\n"
    )
    packages = PackageIndex([root.parent])
    g = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), g, packages, headless=True).start()
    return g


def _costmap(
    graph: Graph, params: dict[str, Any], name: str = "move_base"
) -> tuple[Node, Costmap2DROS]:
    node = graph.create_node(name)
    for key, value in params.items():
        node.set_param(f"~global_costmap/{key}", value)
    buffer = TFBuffer()
    node.subscribe("/tf", "tf2_msgs/TFMessage", buffer.set_message)
    node.subscribe("/tf_static", "tf2_msgs/TFMessage", lambda m: buffer.set_message(m, static=True))
    return node, Costmap2DROS(node, "global_costmap", buffer)


def _scan(stamp_ns: int, ranges: list[float]) -> Any:
    count = len(ranges)
    return types().cls("sensor_msgs/LaserScan")(
        build.header(stamp_ns, "laser"),
        -math.pi / 4,
        math.pi / 4,
        math.pi / 2 / (count - 1),
        0.0,
        0.1,
        0.1,
        5.0,
        np.asarray(ranges, dtype=np.float32),
        np.zeros(0, dtype=np.float32),
    )


def test_the_costmap_node_publishes_the_static_map_inflated_and_marks_a_scan(
    graph: Graph,
) -> None:
    node, costmap = _costmap(graph, PARAMS)
    probe = graph.create_node("probe")
    grids: list[Any] = []
    updates: list[Any] = []
    footprints: list[Any] = []
    probe.subscribe("/move_base/global_costmap/costmap", "nav_msgs/OccupancyGrid", grids.append)
    probe.subscribe(
        "/move_base/global_costmap/costmap_updates",
        "map_msgs/OccupancyGridUpdate",
        updates.append,
    )
    probe.subscribe(
        "/move_base/global_costmap/footprint", "geometry_msgs/PolygonStamped", footprints.append
    )
    costmap.start()
    graph.run(duration=1.0)
    pose = costmap.robot_pose()
    assert pose is not None
    np.testing.assert_allclose(pose, [1.0, 1.0, 0.0], atol=1e-12)
    assert grids
    msg = grids[-1]
    assert msg.header.frame_id == "map"
    assert (msg.info.width, msg.info.height, msg.info.resolution) == (80, 60, 0.05)
    data = np.asarray(msg.data, dtype=np.int8).reshape(60, 80)
    grid = costmap.grid()
    assert np.array_equal(data, COST_TRANSLATION[grid.costs])
    assert data[0, 40] == 100  # a wall is lethal
    assert data[1, 40] == 99  # inscribed next to it
    assert data[30, 75] == -1  # unknown space is tracked
    assert 0 < data[5, 40] < 99
    assert data[30, 30] == 0
    polygon = footprints[-1].polygon.points
    assert len(polygon) == 16
    assert math.hypot(polygon[0].x - 1.0, polygon[0].y - 1.0) == pytest.approx(0.185)

    # a scan: an obstacle 1 m ahead of the laser (at x = 2.1), every other beam out of range
    ranges = [math.inf] * 11
    ranges[5] = 1.0
    probe_pub = probe.publisher("/scan", "sensor_msgs/LaserScan")
    probe_pub.publish(_scan(node.now_ns(), ranges))
    graph.run(duration=1.0)
    cell = costmap.grid().world_to_map(2.1, 1.0)
    assert cell is not None
    assert costmap.grid().costs[cell[1], cell[0]] == LETHAL
    assert updates
    last = updates[-1]
    assert last.x <= cell[0] < last.x + last.width
    assert last.y <= cell[1] < last.y + last.height
    assert costmap.inscribed_radius == pytest.approx(0.185 * math.cos(math.pi / 16), abs=0.01)
    assert costmap.global_frame == "map"
    assert costmap.robot_base_frame == "base_footprint"

    costmap.stop()
    count = len(grids) + len(updates)
    graph.run(duration=1.0)
    assert len(grids) + len(updates) == count
    costmap.reset()
    assert (costmap.grid().costs == NO_INFORMATION).all()
    assert costmap.update_now()
    assert costmap.grid().costs[30, 30] == 0


def test_the_translation_table() -> None:
    assert COST_TRANSLATION[[0, 1, 126, 252, 253, 254, 255]].tolist() == [0, 1, 49, 98, 99, 100, -1]


def test_a_bad_parameter_is_one_error_naming_it(graph: Graph) -> None:
    with pytest.raises(ValueError, match=r"'footprint' must be a polygon of at least 3"):
        _costmap(graph, {**PARAMS, "footprint": [[0.1, 0.1]]})
    with pytest.raises(ValueError, match=r"'map_type' must be 'costmap' or 'voxel', not 'grid'"):
        _costmap(graph, {**PARAMS, "map_type": "grid"}, "move_base_2")


def test_scans_and_clouds_become_points() -> None:
    scan = _scan(0, [1.0, math.inf, 0.05, 5.0, float("nan"), 2.0, 1.0, 1.0, 1.0, 1.0, 1.0])
    points = scan_points(scan, inf_is_valid=False)
    assert len(points) == 7  # inf, below range_min, at range_max and nan are dropped
    np.testing.assert_allclose(points[0], [math.cos(-math.pi / 4), math.sin(-math.pi / 4), 0])
    with_inf = scan_points(scan, inf_is_valid=True)
    assert len(with_inf) == 8
    assert np.hypot(*with_inf[1, :2]) == pytest.approx(5.0 - 1e-4)
    cls = types().cls
    field = cls("sensor_msgs/PointField")
    xyz = np.array([[1.0, 2.0, 3.0], [np.nan, 0.0, 0.0], [4.0, 5.0, 6.0]], dtype="<f4")
    cloud = cls("sensor_msgs/PointCloud2")(
        build.header(0, "laser"),
        1,
        3,
        [field("x", 0, 7, 1), field("y", 4, 7, 1), field("z", 8, 7, 1)],
        False,
        12,
        36,
        np.frombuffer(xyz.tobytes(), dtype=np.uint8),
        True,
    )
    np.testing.assert_allclose(cloud_points(cloud), [[1, 2, 3], [4, 5, 6]])
