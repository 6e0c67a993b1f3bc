"""joy_node fed by a gamepad in the browser: Chromium on the node's page with a synthetic
gamepad (navigator.getGamepads overridden) drives, through teleop_twist_joy, the turtle;
axes come signed as ROS's driver gives them, with the dead zone cut out; the page's state
endpoint refuses a request without its secret."""

from __future__ import annotations

import urllib.error
import urllib.request
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.nodes.joy import ros_axis
from belvedere.packages import PackageIndex
from tests.conftest import free_port
from tests.viewer.test_browser import chromium_page
from tests.waiting import wait_until

GAMEPAD = """(state) => {
  window.__pad = state;
  navigator.getGamepads = () => [{
    id: "synthetic pad", connected: true, index: 0, mapping: "standard",
    axes: window.__pad.axes,
    buttons: window.__pad.buttons.map(b => ({pressed: b === 1, value: b})),
  }];
}"""


def test_axes_as_rosjoy_gives_them() -> None:
    assert ros_axis(-1.0, 0.05) == pytest.approx(1.0)  # stick up: +1
    assert ros_axis(0.04, 0.05) == 0.0
    assert ros_axis(0.525, 0.05) == pytest.approx(-0.5)


def joy_turtle_launch(folder: Path, port: int, **joy_params: object) -> Path:
    """turtlesim driven by teleop_twist_joy from a joy_node (its page on ``port``, a 0.1
    dead zone, and ``joy_params``)."""
    extra = "".join(f'<param name="{k}" value="{v}"/>' for k, v in joy_params.items())
    launch = folder / "joy.launch"
    launch.write_text(
        f"""<launch>
          <node pkg="turtlesim" type="turtlesim_node" name="sim"/>
          <node pkg="joy" type="joy_node" name="joy_node">
            <param name="port" value="{port}"/>
            <param name="deadzone" value="0.1"/>{extra}
          </node>
          <node pkg="teleop_twist_joy" type="teleop_node" name="teleop">
            <param name="scale_linear" value="1.0"/>
            <remap from="cmd_vel" to="/turtle1/cmd_vel"/>
          </node>
        </launch>"""
    )
    return launch


def test_a_browser_gamepad_drives_the_turtle(tmp_path: Path) -> None:
    port = free_port()
    launch = joy_turtle_launch(tmp_path, port)
    packages = PackageIndex([])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True)
    runtime.start()
    joys: list[Any] = []
    poses: list[Any] = []
    probe = graph.create_node("probe")
    probe.subscribe("/joy", "sensor_msgs/Joy", joys.append, queue_size=100)
    probe.subscribe("/turtle1/pose", "turtlesim/Pose", poses.append, queue_size=1000)
    graph.run(duration=0.1)
    url = graph.params.get("/joy_node/page_url")
    assert url == f"http://127.0.0.1:{port}/"
    with pytest.raises(urllib.error.HTTPError, match="403"):
        urllib.request.urlopen(urllib.request.Request(f"{url}state", data=b"{}"), timeout=10)
    try:
        with chromium_page(url, (640, 480)) as page:
            # left stick pushed up to -0.55 (half way past the dead zone), enable button held
            page.evaluate(GAMEPAD, {"axes": [0.0, -0.55, 0.0, 0.0], "buttons": [1, 0, 0, 0]})

            def joy_arrived() -> bool:
                graph.run(duration=0.05)
                return bool(joys)

            wait_until(joy_arrived, what="a Joy message from the page")
            page.wait_for_function("document.body.innerText.includes('synthetic pad')")
            start_x = poses[-1].x
            graph.run(duration=1.0)
    finally:
        runtime.close()
    assert list(joys[0].axes) == pytest.approx([0.0, 0.5, 0.0, 0.0])
    assert list(joys[0].buttons) == [1, 0, 0, 0]
    # teleop_twist_joy: axis 1 times 1.0 m/s while enabled; the turtle runs on it (until
    # turtlesim's one second without a command: the pad sent one state, no repeats)
    assert max(p.linear_velocity for p in poses) == pytest.approx(0.5)
    assert poses[-1].x > start_x + 0.3
