"""The viewer faults a new user meets (issue 33 §2), without a browser: a Kinect's coloured
cloud shown in its colours, rviz's dark background, ``rviz --help``, a taken port."""

from __future__ import annotations

import logging
import os
import socket
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.cli import main
from belvedere.graph import Graph
from belvedere.nodes.rviz import usage
from belvedere.viewer import Viewer
from tests.conftest import free_port
from tests.viewer.kinect import kinect_cloud
from tests.waiting import wait_until

RVIZ = Path("/usr/bin/rviz")


def _drawn_colours(values: dict[str, Any] | None) -> tuple[str, set[tuple[int, ...]]]:
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="camera")
    try:
        display = viewer.add_display("PointCloud2", "/points", values=values)
        pub = graph.create_node("kinect").publisher("/points", "sensor_msgs/PointCloud2")
        graph.start(rtf=None)
        graph.executor.post(lambda: pub.publish_data(kinect_cloud()))
        wait_until(lambda: "points" in display.handles, what="the cloud drawn")
        handle = display.handles["points"]
        colours = {tuple(c) for c in np.asarray(handle.colors).reshape(-1, 3).tolist()}
        return str(display.values["Color Transformer"]), colours
    finally:
        viewer.close()
        graph.shutdown()


def test_a_new_cloud_display_shows_a_kinects_colours() -> None:
    """rviz picks RGB8 for a new display of a cloud with an rgb field."""
    transformer, colours = _drawn_colours(None)
    assert transformer == "RGB8"
    assert colours == {(255, 0, 0), (0, 255, 0)}


@pytest.mark.parametrize("chosen", ["", "Intensity"])
def test_a_chosen_transformer_is_kept(chosen: str) -> None:
    """A config's own choice stays (rviz saves an unchosen one as "", which is no choice)."""
    transformer, colours = _drawn_colours({"Color Transformer": chosen})
    if chosen:
        assert transformer == "Intensity"
        assert colours == {(255, 255, 255)}  # no intensity field: the flat colour
    else:
        assert transformer == "RGB8"


def test_the_background_without_a_config_is_rvizs_grey() -> None:
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port())
    try:
        assert tuple(viewer.background.value) == (48, 48, 48)
    finally:
        viewer.close()
        graph.shutdown()


def test_rviz_help_prints_the_usage_and_starts_no_viewer(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["run", "--headless", "rviz", "rviz", "--help"]) == 1  # as rviz exits
    out = capsys.readouterr().out
    assert out == usage()
    assert out.startswith("rviz command line options:\n  -h [ --help ]")


@pytest.mark.skipif(not RVIZ.exists(), reason="Debian's rviz is not installed")
def test_rviz_help_is_debian_rvizs() -> None:
    done = subprocess.run(
        [str(RVIZ), "--help"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
        env={**os.environ, "QT_QPA_PLATFORM": "offscreen"},
    )
    assert done.returncode == 1
    theirs = "".join(line for line in done.stdout.splitlines(True) if "[ INFO]" not in line)
    assert usage() == theirs


def test_a_viewer_on_a_taken_port_says_where_it_went(caplog: pytest.LogCaptureFixture) -> None:
    graph = Graph(sim_time=False)
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        with caplog.at_level(logging.WARNING):
            viewer = Viewer(graph, port=port)
        try:
            moved = viewer.server.get_port()
            assert moved != port
            assert f"viewer: port {port} is taken; serving on port {moved} instead" in caplog.text
        finally:
            viewer.close()
            graph.shutdown()


def test_odometry_draws_solid_arrows_and_its_covariance() -> None:
    """rviz's Odometry defaults: an arrow of shaft 1 m (radius 0.05) and head 0.3 m (radius
    0.1), the position's covariance as an ellipse of two standard deviations each way, the
    heading's as a fan of two each side."""
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="odom")
    try:
        display = viewer.add_display("Odometry", "/odom")
        pub = graph.create_node("base").publisher("/odom", "nav_msgs/Odometry")
        graph.start(rtf=None)
        covariance = [0.0] * 36
        covariance[0], covariance[7], covariance[35] = 0.04, 0.01, 0.09  # std 0.2 m, 0.1 m, 0.3 rad
        graph.executor.post(
            lambda: pub.publish_data(
                {
                    "header": {"frame_id": "odom"},
                    "pose": {
                        "pose": {"position": {"x": 1.0}, "orientation": {"w": 1.0}},
                        "covariance": covariance,
                    },
                }
            )
        )
        wait_until(lambda: "orientation" in display.handles, what="the odometry drawn")
        arrows = display.handles["arrows"]
        assert np.asarray(arrows.points) == pytest.approx(np.array([[[1, 0, 0], [2.3, 0, 0]]]))
        assert (arrows.shaft_radius, arrows.head_radius, arrows.head_length) == (0.05, 0.1, 0.3)
        ellipse = np.asarray(display.handles["position"].vertices)
        spans = ellipse.max(axis=0) - ellipse.min(axis=0)
        assert spans == pytest.approx([0.8, 0.4, 2e-3], abs=1e-3)  # two std each way; flat in z
        fan = np.asarray(display.handles["orientation"].vertices)
        angles = np.arctan2(fan[1:, 1], fan[1:, 0] - 1.0)
        assert angles.max() == pytest.approx(0.6)
        assert angles.min() == pytest.approx(-0.6)
        display.set_value("Covariance", False)
        assert "position" not in display.handles
        assert "orientation" not in display.handles
        display.set_value("Shape", "Axes")
        assert "axes" in display.handles
        assert "arrows" not in display.handles
    finally:
        viewer.close()
        graph.shutdown()
