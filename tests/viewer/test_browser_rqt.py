"""rqt_plot, rqt_console and rqt_image_view as pages in a real browser (Debian's Chromium), on
running simulations: the plot of /odom's x rises as /cmd_vel drives the robot, the console
lists a node's warning and filters it away, the image view shows the camera's frames as they
come."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from io import BytesIO
from typing import Any

import numpy as np
import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.kinematic import KinematicSimulation
from belvedere.sim.physics import PhysicsSimulation
from belvedere.viewer import ConsolePage, ImagePage, PlotPage, ToolPage
from belvedere.world import read_world
from tests.conftest import EXAMPLES, free_port
from tests.viewer.docs_screenshots import docs_screenshot
from tests.viewer.test_browser import MBOT, SOFTWARE_WEBGL_NOTICE, chromium_page
from tests.waiting import wait_until

pytestmark = pytest.mark.browser

CAMERA_BOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_camera_gazebo.xacro"
PLOT_BLUE = (31, 119, 180)
"""The first series' stroke (#1f77b4)."""
COUNT_FRAMES = """() => {
  window.__frames = new Set();
  const note = (img) => { if (img.src.startsWith('blob:')) window.__frames.add(img.src); };
  document.querySelectorAll('img').forEach(note);
  new MutationObserver((changes) => changes.forEach((c) => {
    if (c.target.tagName === 'IMG') note(c.target);
    c.addedNodes.forEach((n) => { if (n.tagName === 'IMG') note(n);
      if (n.querySelectorAll) n.querySelectorAll('img').forEach(note); });
  })).observe(document.body, {subtree: true, childList: true, attributes: true,
                              attributeFilter: ['src']});
}"""


@contextlib.contextmanager
def tool_page(url: str) -> Iterator[Any]:
    """Debian's Chromium, headless, on an rqt page."""
    with chromium_page(url, (1100, 760)) as page:
        page.add_style_tag(content=f"#{SOFTWARE_WEBGL_NOTICE} {{ display: none !important; }}")
        yield page


def stroke_ends(page: Any) -> tuple[int, int] | None:
    """The pixel rows of the plotted line's left and right ends (None before it is drawn)."""
    from PIL import Image

    shot = page.locator(".uplot canvas").first.screenshot()
    rgb = np.asarray(Image.open(BytesIO(shot)).convert("RGB")).astype(int)
    near = (np.abs(rgb - np.array(PLOT_BLUE)).sum(axis=2) < 60).nonzero()
    if near[1].size < 20:
        return None
    left, right = near[1].min(), near[1].max()
    return int(near[0][near[1] == left].mean()), int(near[0][near[1] == right].mean())


def test_the_plot_of_odom_x_follows_the_robot() -> None:
    graph = Graph()
    KinematicSimulation(graph, RobotModel.from_path(MBOT))
    cmd = graph.create_node("driver").publisher("/cmd_vel", "geometry_msgs/Twist")
    plot = PlotPage(
        graph.create_node("rqt_plot"),
        ["/odom/pose/pose/position/x:y"],
        ToolPage("rqt_plot", port=free_port()),
    )
    graph.start(rtf=1.0)
    try:
        with tool_page(plot.page.url) as page:
            page.get_by_text("/odom/pose/pose/position/x").first.wait_for()
            cmd.publish_data({"linear": {"x": 0.5}})

            def risen() -> bool:
                xs, x, _y = plot.data()
                return xs.size > 20 and x[-1] > 1.0

            wait_until(risen, what="/odom's x past 1 m in the plot", detail=plot.data)
            ends = wait_until(
                lambda: (e := stroke_ends(page)) is not None and e[1] < e[0] - 20 and e,
                what="the plotted line rising to the right",
                detail=lambda: stroke_ends(page),
            )
            assert ends
            docs_screenshot(page, "rqt_plot")
            page.get_by_text("Pause").first.click()
            wait_until(lambda: plot.paused.value, what="the plot paused from the page")
    finally:
        plot.close()
        graph.shutdown()


def test_the_console_lists_a_nodes_warning_and_filters_it() -> None:
    graph = Graph()
    KinematicSimulation(graph, RobotModel.from_path(MBOT))
    console = ConsolePage(
        graph.create_node("rqt_console"), ToolPage("rqt_console", port=free_port())
    )
    driver = graph.create_node("driver")
    graph.start(rtf=1.0)
    try:
        with tool_page(console.page.url) as page:
            driver.logger.info("driving to the door")
            driver.logger.warning("battery low: %d%%", 15)
            driver.logger.error("left wheel stalled")
            row = page.locator("table.rqt-log tr", has_text="battery low: 15%")
            row.wait_for()
            cells = row.locator("td").all_inner_texts()
            assert cells[1:3] == ["WARN", "/driver"]
            assert cells[5].endswith(
                ":test_the_console_lists_a_nodes_warning_and_filters_it:"
                + cells[5].rsplit(":", 1)[1]
            )
            docs_screenshot(page, "rqt_console")
            # viser's text boxes carry no id their label names: the input after the label
            page.locator("xpath=//label[text()='Message contains']/following::input[1]").fill(
                "stalled"
            )
            row.wait_for(state="detached")
            page.locator("table.rqt-log tr", has_text="left wheel stalled").wait_for()
    finally:
        console.close()
        graph.shutdown()


def test_the_image_view_shows_the_camera_as_it_comes() -> None:
    packages = PackageIndex([EXAMPLES])
    world = read_world(EXAMPLES / "mbot_gazebo/worlds/playground.world", packages=packages)
    graph = Graph()
    sim = PhysicsSimulation(graph, world)
    sim.spawn(RobotModel.from_path(CAMERA_BOT), name="mbot", packages=packages)
    turn = graph.create_node("driver").publisher("/cmd_vel", "geometry_msgs/Twist")
    view = ImagePage(
        graph.create_node("rqt_image_view"), ToolPage("rqt_image_view", port=free_port())
    )
    graph.start(rtf=1.0)
    try:
        with tool_page(view.page.url) as page:
            wait_until(lambda: view.topic == "/camera/image_raw", what="the camera picked")
            page.evaluate(COUNT_FRAMES)
            # viser sends a picture only when it differs from the last: the robot turns, so
            # every frame the camera takes is new
            turn.publish_data({"angular": {"z": 0.6}})
            wait_until(
                lambda: page.evaluate("window.__frames.size") >= 10,
                what="ten camera frames in the page",
                detail=lambda: (page.evaluate("window.__frames.size"), view.sent, view.received),
            )
            shown = page.locator("img[src^='blob:']").first.screenshot()
            from PIL import Image

            pixels = np.asarray(Image.open(BytesIO(shown)).convert("RGB")).astype(int)
            assert pixels.std() > 10, "the camera's picture, not a blank frame"
            assert view.shape is not None
            assert view.shape[2] == "rgb8"
            docs_screenshot(page, "rqt_image_view")
    finally:
        view.close()
        graph.shutdown()
