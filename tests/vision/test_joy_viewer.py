"""joy_node fed by a gamepad in the VIEWER's page: Chromium on the viewer with a synthetic
gamepad (navigator.getGamepads overridden) drives the turtle through teleop_twist_joy, joy_node
applying its ``~deadzone`` and ``~autorepeat_rate``; the panel names the pad, and says so when
it goes. joy_node in another process (``belvedere run``) takes the pad as well."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph, ZenohTransport
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.msgs import GAMEPAD_TOPIC
from belvedere.packages import PackageIndex
from belvedere.viewer import Viewer
from tests.conftest import free_port
from tests.viewer.docs_screenshots import DOCS_SCREENSHOTS, docs_screenshot
from tests.viewer.test_browser import SOFTWARE_WEBGL_NOTICE, VIEWPORT, chromium_page
from tests.vision.test_joy_browser import GAMEPAD, joy_turtle_launch
from tests.waiting import DEADLINE, wait_until

pytestmark = pytest.mark.browser

TAMPER = """(text) => {
  const field = [...document.querySelectorAll("input")].find((i) => i.value.startsWith("gamepad:"));
  const setter = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value").set;
  setter.call(field, "gamepad:" + text);
  field.dispatchEvent(new Event("input", {bubbles: true}));
}"""
UNPLUGGED = "() => { navigator.getGamepads = () => [null, null, null, null]; }"


def test_a_gamepad_in_the_viewer_drives_the_turtle(tmp_path: Path) -> None:
    launch = joy_turtle_launch(tmp_path, free_port(), autorepeat_rate=5)
    packages = PackageIndex([])
    graph = Graph()
    runtime = LaunchRuntime(
        load_launch(launch, packages=packages),
        graph,
        packages,
        viewer_options={"port": free_port()},
    )
    runtime.start()  # turtlesim asks for the viewer, as with `belvedere launch`
    viewer = runtime.viewer
    assert viewer is not None
    joys: list[Any] = []
    poses: list[Any] = []
    probe = graph.create_node("probe")
    probe.subscribe("/joy", "sensor_msgs/Joy", joys.append, queue_size=100)
    probe.subscribe("/turtle1/pose", "turtlesim/Pose", poses.append, queue_size=1000)

    def running(check: Any) -> Any:
        def step() -> bool:
            graph.run(duration=0.05)
            return bool(check())

        return step

    try:
        with chromium_page(viewer.url, VIEWPORT) as page:
            page.evaluate(GAMEPAD, {"axes": [0.0, -0.55, 0.0, 0.0], "buttons": [1, 0, 0, 0]})
            # the folder shows once joy_node is seen listening; the page then sends the pad
            wait_until(running(lambda: joys), what="a Joy message from the viewer's page")
            assert graph.topics[GAMEPAD_TOPIC].publishers[0].node is viewer.node
            page.wait_for_function("document.body.innerText.includes('Gamepad: synthetic pad')")
            start_x = poses[-1].x
            sent = len(joys)
            graph.run(duration=2.0)
            # the pad did not change: joy_node repeated its state at 5 Hz, and the turtle,
            # which stops a second after its last command, ran the whole two seconds
            assert 9 <= len(joys) - sent <= 11
            assert poses[-1].linear_velocity == pytest.approx(0.5)
            assert poses[-1].x > start_x + 0.9
            if os.environ.get(DOCS_SCREENSHOTS):
                page.add_style_tag(content=f"#{SOFTWARE_WEBGL_NOTICE} {{ display: none; }}")
                page.wait_for_selector("canvas")
                page.get_by_text("Gamepad: synthetic pad").scroll_into_view_if_needed()
                docs_screenshot(page, "gamepad")
            page.evaluate(UNPLUGGED)
            page.wait_for_function("document.body.innerText.includes('No gamepad')")
            graph.run(duration=0.05)
            sent = len(joys)
            graph.run(duration=1.0)
            assert len(joys) == sent  # the pad went: no more repeats
    finally:
        runtime.close()
    assert list(joys[0].axes) == pytest.approx([0.0, 0.5, 0.0, 0.0])
    assert list(joys[0].buttons) == [1, 0, 0, 0]
    assert viewer.gamepad.rejected == 0


def test_a_joy_node_in_another_process_takes_the_viewers_gamepad(endpoint: str) -> None:
    """``belvedere run joy joy_node`` beside a process with the viewer (as beside
    ``belvedere sim``): the pad goes over the graph on /viewer/gamepad and comes back as
    /joy from the other process."""
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    viewer = Viewer(graph, port=free_port())
    joys: list[Any] = []
    graph.create_node("probe").subscribe("/joy", "sensor_msgs/Joy", joys.append)
    graph.start(rtf=None)
    run = [sys.executable, "-m", "belvedere", "run", "joy", "joy_node", f"_port:={free_port()}"]
    joy_node = subprocess.Popen(run, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        wait_until(
            lambda: viewer.gamepad.pub.wanted or joy_node.poll() is not None,
            what="joy_node subscribing to the viewer's gamepad",
        )
        assert joy_node.poll() is None, joy_node.communicate()[1]
        with chromium_page(viewer.url, VIEWPORT) as page:
            page.evaluate(GAMEPAD, {"axes": [0.3, 0.0], "buttons": [0, 1]})
            wait_until(lambda: joys, what="/joy from the other process")
            page.wait_for_function("document.body.innerText.includes('Gamepad: synthetic pad')")
            # a page changed by hand: what it writes into the State field is checked, not run
            page.evaluate(TAMPER, '{"id": "x", "axes": ["alert(1)"], "buttons": [1]}')
            wait_until(lambda: viewer.gamepad.rejected == 1, what="the bad state refused")
            assert viewer.gamepad.state is not None
            assert viewer.gamepad.state.id == "synthetic pad"
    finally:
        joy_node.terminate()
        joy_node.communicate(timeout=DEADLINE)
        viewer.close()
        graph.shutdown()
    assert list(joys[0].axes) == pytest.approx([-0.2632, 0.0], abs=1e-3)  # (0.3-0.05)/0.95
    assert list(joys[0].buttons) == [0, 1]
    assert len(joys) == 1  # the refused state sent nothing
