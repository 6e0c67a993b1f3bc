"""The viewer in a real browser: Debian's Chromium, headless, software WebGL, via Playwright."""

from __future__ import annotations

import contextlib
import math
import shutil
import socket
import time
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.tf import JointStatePublisher, RobotStatePublisher, TransformListener
from belvedere.viewer import Viewer
from belvedere.viewer._viewer import CAMERA_FOV, CAMERA_LOOK_AT, CAMERA_POSITION
from tests.conftest import EXAMPLES

pytestmark = pytest.mark.browser

MBOT = EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"
VIEWPORT = (1000, 700)
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


def project(point: tuple[float, float, float]) -> tuple[float, float]:
    """Screen pixel of a world point under the viewer's initial camera."""
    eye, target = np.array(CAMERA_POSITION), np.array(CAMERA_LOOK_AT)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rel = np.asarray(point) - eye
    x, y, z = rel @ right, rel @ up, rel @ forward
    f = 1.0 / math.tan(CAMERA_FOV / 2)
    w, h = VIEWPORT
    aspect = w / h
    return (w / 2 * (1 + f * x / (z * aspect)), h / 2 * (1 - f * y / z))


class Scene:
    def __init__(self) -> None:
        self.model = RobotModel.from_path(MBOT)
        self.graph = Graph(sim_time=False)
        RobotStatePublisher(self.graph.create_node("robot_state_publisher"), self.model)
        self.jsp = JointStatePublisher(self.graph.create_node("joint_state_publisher"), self.model)
        self.listener = TransformListener(self.graph.create_node("test_listener"))
        self.node = self.graph.create_node("test")
        self.joint_states: list[Any] = []
        self.goals: list[Any] = []
        self.node.subscribe("/joint_states", "sensor_msgs/JointState", self.joint_states.append)
        self.node.subscribe(
            "/move_base_simple/goal", "geometry_msgs/PoseStamped", self.goals.append
        )
        self.viewer = Viewer(
            self.graph, model=self.model, port=_free_port(), joint_publisher=self.jsp
        )
        self.graph.start(rtf=None)

    def close(self) -> None:
        self.viewer.close()
        self.graph.shutdown()


@pytest.fixture(scope="module")
def scene() -> Iterator[Scene]:
    s = Scene()
    yield s
    s.close()


@contextlib.contextmanager
def browser_page(url: str) -> Iterator[Any]:
    """Debian's Chromium, headless, on ``url``, with the viewer's first frames drawn."""
    if shutil.which("chromium") is None:
        pytest.skip("Debian's chromium is not installed")
    playwright = pytest.importorskip("playwright.sync_api")
    with playwright.sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=shutil.which("chromium"), headless=True, args=CHROMIUM_ARGS
        )
        page = browser.new_page(viewport={"width": VIEWPORT[0], "height": VIEWPORT[1]})
        page.goto(url)
        page.wait_for_selector("canvas", timeout=30000)
        time.sleep(2.0)  # software WebGL: let the first frames reach the canvas
        try:
            yield page
        finally:
            browser.close()


@pytest.fixture(scope="module")
def page(scene: Scene) -> Iterator[Any]:
    started = time.monotonic()
    with browser_page(scene.viewer.url) as page:
        frames = scene.viewer.frames_rendered
        _wait(lambda: scene.viewer.frames_rendered > frames + 3)
        print(f"first frame in the browser after {time.monotonic() - started:.2f} s")  # noqa: T201
        yield page


def _wait(condition: Any, timeout: float = 10.0) -> bool:
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.05)
    return True


def _pixel(page: Any, xy: tuple[float, float]) -> tuple[int, int, int]:
    from io import BytesIO

    from PIL import Image

    image = Image.open(BytesIO(page.screenshot())).convert("RGB")
    r, g, b = image.getpixel((round(xy[0]), round(xy[1])))  # type: ignore[misc]
    return (r, g, b)


def test_robot_renders_where_it_should(scene: Scene, page: Any) -> None:
    # the top of the base (URDF "yellow": rgba 1 0.4 0, lit): 0.11 + 0.08 above base_footprint
    r, g, b = _pixel(page, project((0.0, 0.0, 0.19)))
    assert r > 200, (r, g, b)
    assert r - b > 100, (r, g, b)
    # the wheel on the camera's side (grey) sits at y = -0.19 (the course's "left" wheel)
    r, g, b = _pixel(page, project((0.0, -0.19 - 0.013, 0.06)))
    assert max(r, g, b) - min(r, g, b) < 30, (r, g, b)  # grey
    assert 100 < r < 240, (r, g, b)


def test_joint_slider_moves_the_wheel(scene: Scene, page: Any) -> None:
    name = "left_wheel_joint"
    # The joint sliders are the ones reaching below zero; the first is left_wheel_joint's.
    thumbs = page.get_by_role("slider")
    thumb = next(
        thumbs.nth(i)
        for i in range(thumbs.count())
        if float(thumbs.nth(i).get_attribute("aria-valuemin") or 0) < 0
    )
    thumb.focus()
    thumb.press("End")  # to the upper limit: a continuous joint's slider spans ±pi

    def published() -> bool:
        return any(
            name in m.name
            and m.position[list(m.name).index(name)] == pytest.approx(math.pi, abs=1e-3)
            for m in scene.joint_states[-3:]
        )

    assert _wait(published)
    time.sleep(0.2)
    t = scene.listener.buffer.lookup_transform("base_link", "left_wheel_link")
    assert abs(2 * math.atan2(t.quat_xyzw[1], t.quat_xyzw[3])) == pytest.approx(math.pi, abs=1e-3)


def test_nav_goal_click_publishes_the_floor_point(scene: Scene, page: Any) -> None:
    page.get_by_role("button", name="2D Nav Goal").click()
    target = (-0.6, -0.9)
    x, y = project((*target, 0.0))
    page.mouse.click(x, y)
    assert _wait(lambda: bool(scene.goals))
    goal = scene.goals[-1].pose.position
    assert math.hypot(goal.x - target[0], goal.y - target[1]) < 0.01
    assert scene.goals[-1].header.frame_id == "base_footprint"


def test_scan_and_map_appear(scene: Scene, page: Any) -> None:
    scan = scene.viewer.add_display("LaserScan", "/scan")
    grid = scene.viewer.add_display("OccupancyGrid", "/map")
    pub_scan = scene.node.publisher("/scan", "sensor_msgs/LaserScan")
    pub_map = scene.node.publisher("/map", "nav_msgs/OccupancyGrid", latch=True)
    cells = [100 if (i // 20) // 5 % 2 else 0 for i in range(20 * 20)]  # 5-row bands
    origin = {"position": {"x": -0.5, "y": -1.0}}
    pub_map.publish_data(
        {
            "header": {"frame_id": "base_footprint"},
            "info": {"resolution": 0.05, "width": 20, "height": 20, "origin": origin},
            "data": cells,
        }
    )
    pub_scan.publish_data(
        {
            "header": {"frame_id": "base_footprint"},
            "angle_min": math.pi - 0.5,
            "angle_max": math.pi + 0.5,
            "angle_increment": 0.01,
            "range_min": 0.1,
            "range_max": 5.0,
            "ranges": [0.8] * 101,
        }
    )
    assert _wait(lambda: "points" in scan.handles and "grid" in grid.handles)
    time.sleep(1.5)
    r, g, b = _pixel(page, project((-0.8, 0.0, 0.0)))  # a scan point straight behind
    assert r > 150, (r, g, b)  # red
    assert max(g, b) < 130, (r, g, b)
    rows = [_pixel(page, project((-0.5 + 0.5, -1.0 + 0.25 * k + 0.125, 0.0))) for k in (0, 1)]
    assert rows[0][0] > 200, rows  # free: white
    assert rows[1][0] < 80, rows  # occupied: black


def test_frame_rate(scene: Scene, page: Any) -> None:
    before, start = scene.viewer.frames_rendered, time.monotonic()
    time.sleep(2.0)
    rate = (scene.viewer.frames_rendered - before) / (time.monotonic() - start)
    print(f"viewer updates: {rate:.1f} Hz")  # noqa: T201
    assert rate >= 29.0


def test_a_viewer_with_a_token_in_the_browser(page: Any) -> None:
    """Served beyond loopback: the printed URL's page connects (its websocket carries the
    token by cookie); the same page without the token is refused."""
    browser = page.context.browser  # the module's browser, in fresh contexts (no cookies)
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, host="0.0.0.0", port=_free_port())  # reached via 127.0.0.1 only
    contexts = [browser.new_context(), browser.new_context()]
    try:
        port = viewer.server.get_port()
        user = contexts[0].new_page()
        user.goto(f"http://127.0.0.1:{port}/?token={viewer.access.token}")
        assert _wait(lambda: len(viewer.server.get_clients()) == 1, timeout=30.0)
        stranger = contexts[1].new_page()
        response = stranger.goto(f"http://127.0.0.1:{port}/")
        assert response.status == 403
        assert "needs its token" in stranger.content()
        assert len(viewer.server.get_clients()) == 1
    finally:
        for context in contexts:
            context.close()
        viewer.close()
        graph.shutdown()
