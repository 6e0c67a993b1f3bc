"""The rqt nodes as ROS users start them: ``<node pkg="rqt_plot" …>`` in a launch file and
``belvedere run rqt_plot rqt_plot …``; rqt_plot takes every sample of a fast topic."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.errors import ParseError
from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from belvedere.viewer import ImagePage, PlotPage, ToolPage
from tests.conftest import free_port

SIM = '<node pkg="turtlesim" type="turtlesim_node" name="sim"/>'


def _launch(tmp_path: Path, body: str) -> tuple[Graph, LaunchRuntime]:
    path = tmp_path / "t.launch"
    path.write_text(f"<launch>\n{body}\n</launch>\n")
    packages = PackageIndex([tmp_path])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(path, packages=packages), graph, packages, headless=True)
    runtime.start()
    return graph, runtime


def _page(runtime: LaunchRuntime, kind: type) -> Any:
    """The page a node of the launch opened (its closer is the page's ``close``)."""
    owners = [getattr(closer, "__self__", None) for closer in runtime.closers]
    return next(owner for owner in owners if isinstance(owner, kind))


def test_rqt_plot_in_a_launch_file_plots_every_pose_of_the_turtle(tmp_path: Path) -> None:
    port = free_port()
    plot_node = (
        '<node pkg="rqt_plot" type="rqt_plot" name="plot" args="/turtle1/pose/x:theta">'
        f'<param name="port" value="{port}"/></node>'
    )
    graph, runtime = _launch(tmp_path, SIM + plot_node)
    try:
        plot = _page(runtime, PlotPage)
        assert plot.page.url == f"http://127.0.0.1:{port}"
        poses: list[Any] = []
        graph.create_node("probe").subscribe("/turtle1/pose", "turtlesim/Pose", poses.append)
        graph.run(duration=2.0)
        assert [s.label for s in plot.series] == ["/turtle1/pose/x", "/turtle1/pose/theta"]
        assert plot.received >= len(poses) > 100  # 62.5 Hz, none dropped
        xs, x, theta = plot.data()
        assert (x[-1], theta[-1]) == pytest.approx((poses[-1].x, poses[-1].theta))
        assert xs[-1] == pytest.approx(2.0, abs=0.02)  # simulated seconds
    finally:
        runtime.close()
        graph.shutdown()


def test_a_path_to_no_number_is_an_error_at_its_launch_line(tmp_path: Path) -> None:
    plot_node = '<node pkg="rqt_plot" type="rqt_plot" name="plot" args="/turtle1/pose/z"/>'
    with pytest.raises(ParseError) as raised:
        _launch(tmp_path, SIM + "\n" + plot_node)
    assert raised.value.location is not None
    assert raised.value.location.line == 3
    assert "/turtle1/pose/z: no field 'z' (fields here: x, y, theta" in raised.value.message


def test_rqt_plot_takes_every_sample_at_100_hz() -> None:
    graph = Graph()
    talker = graph.create_node("talker")
    counter = talker.publisher("/count", "std_msgs/Float64")
    sent = [0]

    def publish() -> None:
        sent[0] += 1
        counter.publish_data({"data": float(sent[0])})

    talker.timer(0.01, publish)
    plot = PlotPage(graph.create_node("rqt_plot"), ["/count/data"], ToolPage("p", port=free_port()))
    try:
        plot.autoscroll.value = False
        graph.run(duration=5.0)
        _xs, values = plot.data()
        assert sent[0] >= 490
        assert values.tolist() == list(np.arange(sent[0] - values.size + 1, sent[0] + 1))
        assert values.size == plot.received
        assert sent[0] - plot.received <= 50  # only those before it subscribed (0.5 s timer)
    finally:
        plot.close()
        graph.shutdown()


def test_rqt_image_view_takes_its_topic_from_its_argument(tmp_path: Path) -> None:
    node = (
        '<node pkg="rqt_image_view" type="rqt_image_view" name="view" args="/front/image">'
        f'<param name="port" value="{free_port()}"/></node>'
    )
    graph, runtime = _launch(tmp_path, node)
    try:
        view = _page(runtime, ImagePage)
        camera = graph.create_node("camera")
        image = camera.publisher("/front/image", "sensor_msgs/Image")
        frame = {"height": 2, "width": 2, "encoding": "mono8", "step": 2, "data": [0, 80, 160, 240]}
        camera.timer(0.1, lambda: image.publish_data(frame))
        graph.run(duration=1.5)
        assert view.topic == "/front/image"
        assert view.received >= 1
    finally:
        runtime.close()
        graph.shutdown()


def test_run_with_an_option_rqt_plot_lacks_is_one_error() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "belvedere", "run", "rqt_plot", "rqt_plot", "--bogus"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 1
    assert "error: /rqt_plot: rqt_plot has no option --bogus" in done.stderr
    assert "Traceback" not in done.stderr
