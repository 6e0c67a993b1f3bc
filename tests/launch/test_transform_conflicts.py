"""Two nodes of a launch that publish the same frame's transform (the course's
nav_cloister_demo.launch runs a static map -> odom beside the localizer): one warning, with
both launch lines; tf keeps whichever came last."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest

from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex


def _start(launch: Path) -> Graph:
    packages = PackageIndex.from_environment(near=launch)
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    return graph


def test_a_static_map_to_odom_beside_a_mapper_is_named_once(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    launch = tmp_path / "both.launch"
    launch.write_text(
        "<launch>\n"
        '  <node pkg="gmapping" type="slam_gmapping" name="slam_gmapping">\n'
        '    <param name="odom_frame" value="odom"/>\n'
        "  </node>\n"
        '  <node pkg="tf" type="static_transform_publisher" name="map_odom_broadcaster"\n'
        '        args="0 0 0 0 0 0 /map /odom 100"/>\n'
        '  <node pkg="tf2_ros" type="static_transform_publisher" name="laser_mount"\n'
        '        args="0 0 0.2 0 0 0 base_link laser"/>\n'
        '  <node pkg="tf2_ros" type="static_transform_publisher" name="laser_again"\n'
        '        args="0 0 0.3 0 0 0 base_link laser"/>\n'
        "</launch>\n"
    )
    with caplog.at_level(logging.WARNING, logger="belvedere"):
        graph = _start(launch)
    graph.shutdown()
    conflicts = [r.getMessage() for r in caplog.records if "two nodes publish" in r.getMessage()]
    assert conflicts == [
        f"warning: two nodes publish the transform map -> odom: /slam_gmapping ({launch}:2:3)"
        f" and /map_odom_broadcaster ({launch}:5:3); tf keeps whichever came last, so "
        "/slam_gmapping's updates win over the static one — remove /map_odom_broadcaster: "
        "/slam_gmapping publishes it itself",
        f"warning: two nodes publish the transform base_link -> laser: /laser_mount "
        f"({launch}:7:3) and /laser_again ({launch}:9:3); tf keeps whichever came last, so "
        "the transform jumps between them — keep one",
    ]


def test_different_frames_are_no_conflict(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    launch = tmp_path / "fine.launch"
    launch.write_text(
        "<launch>\n"
        '  <node pkg="gmapping" type="slam_gmapping" name="slam_gmapping"/>\n'
        '  <node pkg="tf" type="static_transform_publisher" name="mount"\n'
        '        args="0 0 0 0 0 0 base_link laser 100"/>\n'
        "</launch>\n"
    )
    with caplog.at_level(logging.WARNING, logger="belvedere"):
        graph = _start(launch)
    graph.shutdown()
    assert not [r for r in caplog.records if "two nodes publish" in r.getMessage()]
