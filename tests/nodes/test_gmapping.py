"""slam_gmapping in the course's gmapping_demo.launch: the physics simulation of the mbot in
the cloister, driven forward; the node's map grows, map → odom is published, the map serves
on ``dynamic_map``, and a bad parameter stops the launch with one message."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.graph import Graph
from belvedere.launch import LaunchError, load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from tests.conftest import EXAMPLES

DEMO = EXAMPLES / "mbot_navigation/launch/gmapping_demo.launch"


def _start(launch: Path) -> Graph:
    packages = PackageIndex.from_environment(near=launch)
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    return graph


def test_the_map_grows_as_the_robot_drives_and_map_to_odom_is_published() -> None:
    graph = _start(DEMO)
    probe = graph.create_node("probe")
    maps: list[Any] = []
    metadata: list[Any] = []
    entropy: list[Any] = []
    map_odom: list[Any] = []

    def on_tf(msg: Any) -> None:
        map_odom.extend(
            t for t in msg.transforms if (t.header.frame_id, t.child_frame_id) == ("map", "odom")
        )

    probe.subscribe("/map", "nav_msgs/OccupancyGrid", maps.append)
    probe.subscribe("/map_metadata", "nav_msgs/MapMetaData", metadata.append)
    probe.subscribe("/slam_gmapping/entropy", "std_msgs/Float64", entropy.append)
    probe.subscribe("/tf", "tf2_msgs/TFMessage", on_tf, queue_size=100)
    cmd = probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    cmd.publish_data({"linear": {"x": 0.4}})
    graph.run(duration=12.0)
    # a map when the first scan came in, then one each map_update_interval (5 s)
    assert len(maps) >= 3
    assert len(metadata) == len(maps)
    assert len(entropy) == len(maps)
    last = maps[-1]
    assert last.header.frame_id == "map"
    assert last.info.resolution == pytest.approx(0.05)
    # the launch's xmin..xmax, ymin..ymax: 20 m x 20 m from (-10, -10)
    assert (last.info.width, last.info.height) == (400, 400)
    assert (last.info.origin.position.x, last.info.origin.position.y) == (-10.0, -10.0)
    known = [int((np.asarray(m.data) >= 0).sum()) for m in maps]
    assert known[-1] > known[0]  # it grows
    assert int((np.asarray(last.data) == 100).sum()) > 200  # walls
    # map → odom every transform_publish_period (0.05 s): about 20 a second
    assert len(map_odom) > 200
    t = map_odom[-1].transform.translation
    assert math.hypot(t.x, t.y) < 0.1  # the physics' odometry is the truth here
    response = probe.call_service("/dynamic_map", "nav_msgs/GetMap")
    assert np.array_equal(np.asarray(response.map.data), np.asarray(last.data))


def test_a_bad_parameter_stops_the_launch(tmp_path: Path) -> None:
    launch = tmp_path / "bad.launch"
    launch.write_text(
        '<launch>\n  <node pkg="gmapping" type="slam_gmapping" name="slam_gmapping">\n'
        '    <param name="delta" value="-0.05"/>\n  </node>\n</launch>\n'
    )
    with pytest.raises(LaunchError) as caught:
        _start(launch)
    assert caught.value.describe() == (
        f"{launch}:2:3: error: /slam_gmapping: parameter delta must be positive, got -0.05"
    )
