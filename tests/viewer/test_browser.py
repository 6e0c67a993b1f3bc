"""The viewer in a real browser: Debian's Chromium, headless, software WebGL, via Playwright."""

from __future__ import annotations

import contextlib
import math
import shutil
import socket
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph, Publisher
from belvedere.sim.kinematic import DiffController, KinematicSimulation
from belvedere.tf import JointStatePublisher, RobotStatePublisher, TransformListener
from belvedere.viewer import Viewer
from belvedere.viewer._chromium import launch_chromium
from belvedere.viewer._views import CAMERA_FOV, CAMERA_LOOK_AT, CAMERA_POSITION
from tests.conftest import EXAMPLES
from tests.viewer.docs_screenshots import docs_screenshot
from tests.waiting import wait_until

pytestmark = pytest.mark.browser

RGB = tuple[int, int, int]
MBOT = EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"
VIEWPORT = (1000, 700)
SOFTWARE_WEBGL_NOTICE = "webgl-software-rendering"
"""The id of viser's "Software WebGL rendering detected" notification."""
VIEW: dict[str, float] = {"x": 0.0, "y": 0.0, "width": VIEWPORT[0], "height": VIEWPORT[1]}
"""The 3D view's box in the page, beside the docked panel: measured when a page opens."""


BROWSER_DEADLINE = 120.0
"""Seconds. Software WebGL compiles its shaders and filters the environment map on the CPU:
the first frame took 43 s on one core shared with a CPU hog (15 s on an idle one)."""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


def project(point: tuple[float, float, float]) -> tuple[float, float]:
    """Screen pixel of a world point under the viewer's initial camera."""
    return project_from(CAMERA_POSITION, CAMERA_LOOK_AT, CAMERA_FOV, point)


def project_from(
    eye_at: tuple[float, float, float],
    look_at: tuple[float, float, float],
    fov: float,
    point: tuple[float, float, float],
) -> tuple[float, float]:
    """Screen pixel of a world point for a camera at ``eye_at`` looking at ``look_at`` (z up,
    vertical field of view ``fov``)."""
    eye, target = np.array(eye_at), np.array(look_at)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rel = np.asarray(point) - eye
    x, y, z = rel @ right, rel @ up, rel @ forward
    f = 1.0 / math.tan(fov / 2)
    w, h = VIEW["width"], VIEW["height"]
    aspect = w / h
    return (VIEW["x"] + w / 2 * (1 + f * x / (z * aspect)), VIEW["y"] + h / 2 * (1 - f * y / z))


def view_centre() -> tuple[float, float]:
    return (VIEW["x"] + VIEW["width"] / 2, VIEW["y"] + VIEW["height"] / 2)


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
            self.graph, model=self.model, port=free_port(), joint_publisher=self.jsp
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


@dataclass(frozen=True)
class DrivenMbot:
    graph: Graph
    sim: KinematicSimulation
    viewer: Viewer
    cmd: Publisher
    """/cmd_vel, to drive it."""
    base: DiffController


@contextlib.contextmanager
def driven_mbot() -> Iterator[DrivenMbot]:
    """The mbot in the kinematic simulation, running in real time, shown by a viewer; closed
    after."""
    model = RobotModel.from_path(MBOT)
    graph = Graph()
    sim = KinematicSimulation(graph, model)
    viewer = Viewer(graph, model=model, port=free_port(), fixed_frame=sim.odom_frame, sim=sim)
    cmd = graph.create_node("driver").publisher("/cmd_vel", "geometry_msgs/Twist")
    graph.start(rtf=1.0)
    base = sim.driver.base
    assert base is not None
    try:
        yield DrivenMbot(graph, sim, viewer, cmd, base)
    finally:
        viewer.close()
        graph.shutdown()


@contextlib.contextmanager
def chromium_page(url: str, viewport: tuple[int, int]) -> Iterator[Any]:
    """Debian's Chromium, headless, on ``url`` in a ``viewport`` (width, height); the test
    skips where Chromium or Playwright is absent."""
    if shutil.which("chromium") is None:
        pytest.skip("Debian's chromium is not installed")
    playwright = pytest.importorskip("playwright.sync_api")
    with playwright.sync_playwright() as p:
        browser = launch_chromium(p, shutil.which("chromium"))
        try:
            page = browser.new_page(viewport={"width": viewport[0], "height": viewport[1]})
            page.set_default_timeout(BROWSER_DEADLINE * 1000)
            page.goto(url)
            yield page
        finally:
            browser.close()


@contextlib.contextmanager
def browser_page(url: str) -> Iterator[Any]:
    """Debian's Chromium, headless, on ``url``, once the page shows the viewer's canvas.

    Tests wait for what they check to be drawn, up to BROWSER_DEADLINE for every step."""
    with chromium_page(url, VIEWPORT) as page:
        page.wait_for_selector("canvas")
        # viser's notice of software WebGL (SwiftShader here) would cover the view's top left
        page.add_style_tag(content=f"#{SOFTWARE_WEBGL_NOTICE} {{ display: none !important; }}")
        canvas = page.locator("canvas").first
        boxes: list[dict[str, float] | None] = []

        def docked() -> bool:
            """The view beside the docked panel, the same box in three looks running."""
            boxes.append(canvas.bounding_box())
            box = boxes[-1]
            return box is not None and box["x"] > 0 and boxes[-3:] == [box] * 3

        wait_until(
            docked,
            what="the panel docked beside the 3D view",
            timeout=BROWSER_DEADLINE,
            interval=0.2,
            detail=lambda: boxes[-3:],
        )
        VIEW.update(boxes[-1] or {})
        yield page


@pytest.fixture(scope="module")
def page(scene: Scene) -> Iterator[Any]:
    with browser_page(scene.viewer.url) as page:
        wait_until(scene.viewer.server.get_clients, what="the browser to connect to the viewer")
        yield page


def _pixel(page: Any, xy: tuple[float, float]) -> RGB:
    """The colour the page shows at ``xy`` (a one-pixel screenshot: cheap to take)."""
    from io import BytesIO

    from PIL import Image

    clip = {"x": round(xy[0]), "y": round(xy[1]), "width": 1, "height": 1}
    image = Image.open(BytesIO(page.screenshot(clip=clip))).convert("RGB")
    r, g, b = image.getpixel((0, 0))  # type: ignore[misc]
    return (r, g, b)


def wait_for_pixel(
    page: Any, xy: tuple[float, float], accept: Callable[[RGB], bool], *, what: str
) -> RGB:
    """The colour at ``xy`` once the browser has drawn one that ``accept`` takes."""
    seen: list[RGB] = []

    def drawn() -> bool:
        seen.append(_pixel(page, xy))
        return accept(seen[-1])

    wait_until(
        drawn,
        what=f"{what} at pixel {xy}",
        timeout=BROWSER_DEADLINE,
        interval=0.1,
        detail=lambda: seen[-3:],
    )
    return seen[-1]


def is_base_yellow(rgb: RGB) -> bool:
    """The mbot base's top (URDF "yellow": rgba 1 0.4 0, lit)."""
    r, _, b = rgb
    return r > 200 and r - b > 100


def test_robot_renders_where_it_should(scene: Scene, page: Any) -> None:
    # the top of the base: 0.11 + 0.08 above base_footprint
    wait_for_pixel(page, project((0.0, 0.0, 0.19)), is_base_yellow, what="the base's yellow top")

    # the wheel on the camera's side (grey) sits at y = -0.19 (the course's "left" wheel)
    def grey(rgb: RGB) -> bool:
        r, g, b = rgb
        return max(r, g, b) - min(r, g, b) < 30 and 100 < r < 240

    wait_for_pixel(page, project((0.0, -0.19 - 0.013, 0.06)), grey, what="the grey left wheel")
    docs_screenshot(page, "display")


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

    wait_until(published, what=f"{name} at pi on /joint_states")

    def wheel_angle() -> float:
        t = scene.listener.buffer.lookup_transform("base_link", "left_wheel_link")
        return abs(2 * math.atan2(t.quat_xyzw[1], t.quat_xyzw[3]))

    # robot_state_publisher turns the joint state into /tf on the graph's own thread
    wait_until(
        lambda: wheel_angle() == pytest.approx(math.pi, abs=1e-3),
        what="left_wheel_link turned by pi on /tf",
        detail=wheel_angle,
    )


def test_nav_goal_click_publishes_the_floor_point(scene: Scene, page: Any) -> None:
    page.get_by_role("button", name="2D Nav Goal").click()
    # the button's callback and the click's are two messages: a click before it is no goal
    wait_until(lambda: scene.viewer.tool == "goal", what="the 2D Nav Goal tool chosen")
    target = (-0.3, -0.8)  # in the view beside the docked panel
    x, y = project((*target, 0.0))
    page.mouse.click(x, y)
    wait_until(lambda: scene.goals, what="a goal on /move_base_simple/goal")
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
    wait_until(
        lambda: "points" in scan.handles and "grid" in grid.handles,
        what="the scan and the map in the viewer's scene",
    )

    def red(rgb: RGB) -> bool:
        r, g, b = rgb
        return r > 150 and max(g, b) < 130

    wait_for_pixel(page, project((-0.8, 0.0, 0.0)), red, what="a red scan point straight behind")
    # x = -0.25: between the Grid display's lines (0.5 m apart), which rviz draws over maps
    free, occupied = (project((-0.25, -1.0 + 0.25 * k + 0.125, 0.0)) for k in (0, 1))
    # free cells: white at the Map's alpha 0.7 over rviz's 48;48;48 background (192)
    wait_for_pixel(page, free, lambda rgb: rgb[0] > 170, what="a white (free) row of the map")
    wait_for_pixel(page, occupied, lambda rgb: rgb[0] < 80, what="a black (occupied) map row")


def test_map_cells_are_drawn_one_by_one(scene: Scene, page: Any) -> None:
    """A checkerboard map at 0.1 m: each cell in its own colour (rviz's free white and
    occupied black at the Map's alpha 0.7 over the background) up to its sides, none blurred
    into its neighbours' grey."""
    pub = scene.node.publisher("/checker", "nav_msgs/OccupancyGrid", latch=True)
    checker = scene.viewer.add_display("Map", "/checker")
    size, resolution, origin = 6, 0.1, (-0.2, 0.6)  # beside the robot, clear of the other map
    pub.publish_data(
        {
            "header": {"frame_id": "base_footprint"},
            "info": {
                "resolution": resolution,
                "width": size,
                "height": size,
                "origin": {"position": {"x": origin[0], "y": origin[1]}},
            },
            "data": [100 * ((i % size + i // size) % 2) for i in range(size * size)],
        }
    )
    try:
        wait_until(lambda: "grid" in checker.handles, what="the checkerboard in the scene")
        # cells 1..3 each way: clear of the Grid display's lines at x = 0 and y = 1
        for row in (1, 2, 3):
            for col in (1, 2, 3):
                centre = (
                    origin[0] + (col + 0.5) * resolution,
                    origin[1] + (row + 0.5) * resolution,
                    0.0,
                )
                xy = project(centre)
                side = abs(project((centre[0] + resolution, *centre[1:]))[0] - xy[0])
                assert side > 6, f"a cell is {side:.1f} px wide: too small to tell apart"
                # the centre and a point near each side: a filtered texture blends a cell's
                # edges with its neighbours', rviz's unfiltered one does not
                for dx, dy in ((0.0, 0.0), (0.2, 0.0), (-0.2, 0.0), (0.0, 0.2), (0.0, -0.2)):
                    at = project((centre[0] + dx * resolution, centre[1] + dy * resolution, 0.0))
                    if (row + col) % 2:
                        wait_for_pixel(
                            page, at, lambda rgb: rgb[0] < 40, what=f"black cell {row, col}"
                        )
                    else:
                        wait_for_pixel(
                            page, at, lambda rgb: rgb[0] > 170, what=f"white cell {row, col}"
                        )
    finally:
        scene.viewer.remove_display(checker)


def test_a_viewer_with_a_token_in_the_browser(page: Any) -> None:
    """Served beyond loopback: the printed URL's page connects (its websocket carries the
    token by cookie); the same page without the token is refused."""
    browser = page.context.browser  # the module's browser, in fresh contexts (no cookies)
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, host="0.0.0.0", port=free_port())  # reached via 127.0.0.1 only
    contexts = [browser.new_context(), browser.new_context()]
    for context in contexts:
        context.set_default_timeout(BROWSER_DEADLINE * 1000)
    try:
        port = viewer.server.get_port()
        user = contexts[0].new_page()
        user.goto(f"http://127.0.0.1:{port}/?token={viewer.access.token}")
        wait_until(
            lambda: len(viewer.server.get_clients()) == 1,
            what="the page with the token to connect",
            timeout=BROWSER_DEADLINE,  # a page loads slowly on one busy core
        )
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
