"""rqt_graph, rqt_tf_tree and urdf_to_graphiz as a user opens them: ``belvedere run`` beside
the course's ArbotiX launch, the printed URL opened in Debian's Chromium; the pictures show
the launch's nodes and topics, every frame and every link of the course robot."""

from __future__ import annotations

import contextlib
import re
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from belvedere.description.graphiz import urdf_to_graphiz
from belvedere.description.urdf import RobotModel
from belvedere.pictures import PicturePage
from tests.conftest import EXAMPLES
from tests.processes import BelvedereProcess
from tests.viewer.docs_screenshots import docs_screenshot
from tests.viewer.test_browser import BROWSER_DEADLINE, chromium_page

pytestmark = pytest.mark.browser

LAUNCH = EXAMPLES / "mbot_description" / "launch" / "arbotix_mbot_with_camera_xacro.launch"
ROBOT = EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo"
ROBOT /= "mbot_with_camera_gazebo.xacro"


@pytest.fixture
def course_launch(endpoint: str) -> Iterator[BelvedereProcess]:
    """The launch, on this test's own graph (hence one per test)."""
    del endpoint
    if shutil.which("dot") is None:
        pytest.skip("Graphviz's dot is not installed")
    process = BelvedereProcess(
        ["launch", "--headless", str(LAUNCH)],
        ready="process[rviz",
        ended="the ArbotiX launch ended",
    )
    yield process
    process.stop()


@contextlib.contextmanager
def browser_page_plain(url: str) -> Iterator[Any]:
    """Debian's Chromium, headless, on ``url`` (a picture's page: no WebGL to wait for)."""
    with chromium_page(url, (1200, 700)) as page:
        yield page


def _tool(args: list[str]) -> tuple[BelvedereProcess, str]:
    tool = BelvedereProcess(["run", *args], ready=args[0] + ":", ended=f"{args[0]} ended")
    url = re.search(r"http://\S+", tool.ready)
    assert url is not None, tool.ready
    return tool, url.group(0)


def _shows(page: Any, names: list[str]) -> None:
    """Wait until the page's picture has a text for each of ``names``."""
    page.wait_for_function(
        "names => { const t = [...document.querySelectorAll('#picture svg text')]"
        ".map(e => e.textContent); return names.every(n => t.some(s => s.includes(n))); }",
        arg=names,
        timeout=BROWSER_DEADLINE * 1000,
    )


def test_rqt_graph_shows_the_launchs_nodes_and_topics(course_launch: BelvedereProcess) -> None:
    tool, url = _tool(["rqt_graph", "rqt_graph"])
    try:
        with browser_page_plain(url) as page:
            nodes = ["/arbotix", "/robot_state_publisher", "/joint_state_publisher"]
            _shows(page, [*nodes, "/joint_states"])
            shown = page.inner_text("#picture")
            assert "/rosout" not in shown  # debug hidden by default
            assert "/belvedere_" not in shown
            assert not re.search(r"/rqt_graph_\d+", shown)  # itself neither
            docs_screenshot(page, "rqt_graph")
            page.select_option("select[name=mode]", "nodes")
            # nodes only: no topic boxes, the topic on the edge between its nodes
            page.wait_for_function(
                "(() => { const t = [...document.querySelectorAll('#picture svg .node title')]"
                ".map(e => e.textContent); return t.length > 0 && !t.some(s => s.startsWith('t_'))"
                " && document.querySelector('#picture svg .edge text')?.textContent"
                " === '/joint_states'; })()"
            )
    finally:
        tool.stop()


def test_rqt_tf_tree_lists_every_frame_of_the_robot(course_launch: BelvedereProcess) -> None:
    model = RobotModel.from_path(ROBOT)
    tool, url = _tool(["rqt_tf_tree", "rqt_tf_tree"])
    try:
        with browser_page_plain(url) as page:
            _shows(page, ["odom", *(link.name for link in model.links)])
            _shows(page, ["Broadcaster: /robot_state_publisher", "Average rate"])
            docs_screenshot(page, "rqt_tf_tree")
    finally:
        tool.stop()


def test_urdf_picture_lists_every_link(tmp_path: Path) -> None:
    if shutil.which("dot") is None:
        pytest.skip("Graphviz's dot is not installed")
    model = RobotModel.from_path(ROBOT)
    gv = urdf_to_graphiz(model)
    page_server = PicturePage("urdf_to_graphiz", lambda _query: gv)
    try:
        with browser_page_plain(page_server.url) as page:
            _shows(page, [link.name for link in model.links] + [j.name for j in model.joints])
            docs_screenshot(page, "urdf_to_graphiz")
    finally:
        page_server.close()
