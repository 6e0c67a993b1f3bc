"""The viewer faults a new user met (issue 33 §2), seen in a real Chromium: the grid hidden by
the walls in front of it, a Kinect's cloud in its own colours, rviz's dark background (drawn
without viser's background pass).

With ``BELVEDERE_DOCS_SCREENSHOTS=docs/images`` each test writes its picture (the "after" of
docs/images/viewfix-*.png; the "before" pictures beside them were taken the same way on the
code before the fix)."""

from __future__ import annotations

import math
from collections.abc import Callable
from io import BytesIO
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.viewer import Viewer
from belvedere.world import read_world
from tests.conftest import DATA, EXAMPLES, free_port
from tests.viewer.docs_screenshots import docs_screenshot
from tests.viewer.kinect import kinect_cloud
from tests.viewer.test_browser import BROWSER_DEADLINE, VIEW, browser_page
from tests.waiting import wait_until

pytestmark = pytest.mark.browser

Image = np.ndarray[Any, np.dtype[np.uint8]]


def _screenshot(page: Any) -> Image:
    from PIL import Image as PILImage

    return np.asarray(PILImage.open(BytesIO(page.screenshot())).convert("RGB"))


def _view_rgb(page: Any) -> tuple[Any, Any, Any]:
    """The 3D view's red, green and blue (as ints), without the side panel and the axes
    gizmo in its bottom corner."""
    rgb = _screenshot(page)[:-120, round(VIEW["x"]) + 2 :].astype(int)
    return rgb[..., 0], rgb[..., 1], rgb[..., 2]


def _blue_room(path: Path) -> Path:
    """Two blue walls behind the origin, 1 m high: the grid runs on under them."""
    walls = [((2.05, 0.0), (0.1, 4.2)), ((0.0, 2.05), (4.2, 0.1))]
    blue = "<material><ambient>0 0 1 1</ambient><diffuse>0 0 1 1</diffuse></material>"
    links = "".join(
        f"<link name='wall_{i}'><pose>{x} {y} 0.5 0 0 0</pose>"
        f"<visual name='v'><geometry><box><size>{sx} {sy} 1</size></box></geometry>{blue}"
        "</visual></link>"
        for i, ((x, y), (sx, sy)) in enumerate(walls)
    )
    path.write_text(
        "<?xml version='1.0'?><sdf version='1.6'><world name='default'>"
        f"<model name='room'><static>true</static>{links}</model></world></sdf>"
    )
    return path


def _is_blue(rgb: Image) -> Any:
    r, g, b = (rgb[..., i].astype(int) for i in range(3))
    return (b > 60) & (b > r + 40) & (b > g + 40)


def _lines_across_walls(rgb: Image) -> int:
    """Grey pixels with wall blue two pixels above and below them in the 3D view: a grid line
    drawn over a wall (a wall's own edge has blue on one side only)."""
    rgb = rgb[:, round(VIEW["x"]) + 2 :]
    blue = _is_blue(rgb)
    r, g, b = (rgb[..., i].astype(int) for i in range(3))
    grey = (abs(r - b) < 30) & (abs(g - b) < 30) & (r > 80)
    inside = grey[2:-2] & blue[:-4] & blue[4:]
    return int(inside.sum())


def test_the_grid_is_hidden_by_the_walls_in_front_of_it(tmp_path: Path) -> None:
    world = read_world(_blue_room(tmp_path / "room.world"), packages=PackageIndex([EXAMPLES]))
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), world=world, fixed_frame="world")
    graph.start(rtf=None)
    try:
        with browser_page(viewer.url) as page:
            wait_until(
                lambda: _is_blue(_screenshot(page)).sum() > 20000,
                what="the blue walls drawn",
                timeout=BROWSER_DEADLINE,
            )
            wait_until(lambda: "grid" in viewer.displays[0].handles, what="the grid drawn")
            page.wait_for_timeout(1000)  # a frame with both drawn
            rgb = _screenshot(page)
            assert _lines_across_walls(rgb) < 20, _lines_across_walls(rgb)
            # the grid is drawn at all: grey lines on the floor, the background between them
            floor = rgb[rgb.shape[0] * 3 // 4 :, rgb.shape[1] // 2 :]
            assert ((floor == (48, 48, 48)).all(axis=2)).mean() > 0.5
            assert ((floor[..., 0] > 90) & (floor[..., 0] < 200)).sum() > 500
            docs_screenshot(page, "viewfix-grid-after")
    finally:
        viewer.close()
        graph.shutdown()


BACKGROUND_PASS = """() => {
    const m = window.__viserMutable;
    let shown = null;
    m.scene.traverse((o) => { if (o.material === m.backgroundMaterial) shown = o.visible; });
    return [shown, m.canvas.style.backgroundColor];
}"""
"""Whether viser's background quad is drawn, and the colour behind the 3D view's canvas."""


def test_the_background_colour_is_the_pages_not_a_pass_of_its_own() -> None:
    """rviz's flat background colour shows behind the 3D view without viser's full-view
    background pass (a software renderer pays for it at every pixel), and follows a change."""
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="map")
    graph.start(rtf=None)
    try:
        with browser_page(viewer.url) as page:

            def most(rgb: Image) -> tuple[int, ...]:
                view = rgb[:-120, round(VIEW["x"]) + 2 :].reshape(-1, 3)
                colours, seen = np.unique(view, axis=0, return_counts=True)
                return tuple(int(c) for c in colours[seen.argmax()])

            for colour in ((48, 48, 48), (10, 90, 200)):
                viewer.set_background(colour)
                wait_until(
                    lambda c=colour: (
                        page.evaluate(BACKGROUND_PASS) == [False, "rgb({}, {}, {})".format(*c)]
                    ),  # type: ignore[misc]
                    what=f"the pass hidden, {colour} behind the view",
                    timeout=BROWSER_DEADLINE,
                    detail=lambda: page.evaluate(BACKGROUND_PASS),
                )
                wait_until(
                    lambda c=colour: most(_screenshot(page)) == c,  # type: ignore[misc]
                    what=f"the view's background {colour}",
                    detail=lambda: most(_screenshot(page)),
                )
    finally:
        viewer.close()
        graph.shutdown()


def test_a_kinect_cloud_shows_its_colours_on_rvizs_background() -> None:
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="camera")
    display = viewer.add_display("PointCloud2", "/points", values={"Size (m)": 0.05})
    pub = graph.create_node("kinect").publisher("/points", "sensor_msgs/PointCloud2", latch=True)
    graph.start(rtf=None)
    graph.executor.post(lambda: pub.publish_data(kinect_cloud()))
    try:
        with browser_page(viewer.url) as page:
            wait_until(lambda: "points" in display.handles, what="the cloud drawn")

            def counts() -> tuple[int, int]:
                r, g, b = _view_rgb(page)
                red = (r > 150) & (g < 80) & (b < 80)
                green = (g > 150) & (r < 80) & (b < 80)
                return int(red.sum()), int(green.sum())

            wait_until(
                lambda: min(counts()) > 1000,
                what="red and green points in the view",
                timeout=BROWSER_DEADLINE,
                detail=counts,
            )
            view = _screenshot(page)[:, round(VIEW["x"]) + 2 :].reshape(-1, 3)
            colours, seen = np.unique(view, axis=0, return_counts=True)
            # rviz's background, not white, is what most of the view shows
            assert tuple(colours[seen.argmax()]) == (48, 48, 48)
            assert display.values["Color Transformer"] == "RGB8"
            docs_screenshot(page, "viewfix-cloud-after")
    finally:
        viewer.close()
        graph.shutdown()


def odometry_with_covariance() -> dict[str, Any]:
    """An odometry message at the origin heading +x: standard deviations 0.2 m along x, 0.1 m
    along y, 0.3 rad of heading."""
    covariance = [0.0] * 36
    covariance[0], covariance[7], covariance[35] = 0.04, 0.01, 0.09
    pose = {"position": {"x": 0.0}, "orientation": {"w": 1.0}}
    return {"header": {"frame_id": "odom"}, "pose": {"pose": pose, "covariance": covariance}}


def test_odometry_shows_a_solid_arrow_and_its_covariance() -> None:
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="odom")
    display = viewer.add_display("Odometry", "/odom")
    pub = graph.create_node("base").publisher("/odom", "nav_msgs/Odometry", latch=True)
    graph.start(rtf=None)
    graph.executor.post(lambda: pub.publish_data(odometry_with_covariance()))
    try:
        with browser_page(viewer.url) as page:
            wait_until(lambda: "orientation" in display.handles, what="the odometry drawn")

            def counts() -> tuple[int, int, int]:
                r, g, b = _view_rgb(page)
                arrow = (r > 150) & (g < 80) & (b < 60)  # rviz's 255; 25; 0, lit
                ellipse = (r > 90) & (b > 90) & (g < r - 40) & (g < b - 40)  # magenta over grey
                fan = (r > 120) & (g > 120) & (b < r - 40)  # yellow over grey
                return int(arrow.sum()), int(ellipse.sum()), int(fan.sum())

            wait_until(
                lambda: min(counts()) > 500,
                what="a solid arrow, a position ellipse and a heading fan in the view",
                timeout=BROWSER_DEADLINE,
                detail=counts,
            )
            docs_screenshot(page, "viewfix-odometry-after")
    finally:
        viewer.close()
        graph.shutdown()


def camera_image(width: int = 640, height: int = 480) -> dict[str, Any]:
    """A camera's rgb8 picture: the left half magenta, the right half cyan."""
    pixels = np.zeros((height, width, 3), dtype=np.uint8)
    pixels[:, : width // 2] = (255, 0, 255)
    pixels[:, width // 2 :] = (0, 255, 255)
    return {
        "header": {"frame_id": "camera"},
        "height": height,
        "width": width,
        "encoding": "rgb8",
        "step": width * 3,
        "data": list(pixels.tobytes()),
    }


def test_a_camera_image_is_shown_beside_the_view_and_in_it() -> None:
    """rviz docks an Image display's panel beside the 3D view; a Camera display's picture
    stands in the scene as well. Before, the picture was the last item of the side panel,
    below the fold."""
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="camera")
    image = viewer.add_display("Image", "/camera/image_raw")
    camera = viewer.add_display("Camera", "/camera/image_raw")
    pub = graph.create_node("camera").publisher("/camera/image_raw", "sensor_msgs/Image")
    graph.start(rtf=None)
    graph.executor.post(lambda: pub.publish_data(camera_image()))
    try:
        with browser_page(viewer.url) as page:
            wait_until(
                lambda: "panel" in image.handles and "frustum" in camera.handles,
                what="the image's panel and the camera's frustum",
            )

            def pictures() -> list[dict[str, float]]:
                """The page's pictures bigger than an icon, top first."""
                found = page.locator("img")
                boxes = (found.nth(k).bounding_box() for k in range(found.count()))
                return sorted((b for b in boxes if b and b["width"] > 100), key=lambda b: b["y"])

            wait_until(lambda: len(pictures()) == 2, what="the two pictures in the page")
            height = page.viewport_size["height"]
            rgb = _screenshot(page)
            for box in pictures():
                assert box["y"] + box["height"] <= height, box  # seen without scrolling
                assert box["x"] > VIEW["x"], box  # beside the side panel, not in it
                y = round(box["y"] + box["height"] / 2)
                left = rgb[y, round(box["x"] + box["width"] / 4)].astype(int)
                right = rgb[y, round(box["x"] + box["width"] * 3 / 4)].astype(int)
                assert np.abs(left - (255, 0, 255)).max() <= 4, left  # the picture's colours
                assert np.abs(right - (0, 255, 255)).max() <= 4, right
            # the camera's picture in the scene too
            view = rgb[:, round(VIEW["x"]) + 2 : round(pictures()[0]["x"]) - 20]
            magenta = (view == (255, 0, 255)).all(axis=2) | (view[..., 1] < 60) & (
                view[..., 0] > 150
            )
            assert magenta.sum() > 200
            docs_screenshot(page, "viewfix-image-after")
    finally:
        viewer.close()
        graph.shutdown()


def test_the_arbotix_launchs_viewer_has_reset_pause_and_step() -> None:
    """The tutorial's §3: the course's ArbotiX launch opens a viewer whose Simulation folder
    resets the driven robot to the origin, as `belvedere sim`'s does."""
    from belvedere.launch import load_launch
    from belvedere.launch._runtime import LaunchRuntime

    launch = EXAMPLES / "mbot_description/launch/arbotix_mbot_with_camera_xacro.launch"
    packages = PackageIndex.from_environment(near=launch)
    graph = Graph()
    runtime = LaunchRuntime(
        load_launch(launch, packages=packages),
        graph,
        packages,
        viewer_options={"port": free_port()},
    )
    odom: list[Any] = []
    graph.create_node("probe").subscribe(
        "/odom", "nav_msgs/Odometry", lambda m: odom.append(m.pose.pose.position.x)
    )
    cmd = graph.create_node("driver").publisher("/cmd_vel", "geometry_msgs/Twist")
    try:
        runtime.start()
        graph.start(rtf=1.0)
        with browser_page(runtime.viewer.url) as page:
            page.get_by_text("Simulation", exact=True).wait_for()
            graph.executor.post(lambda: cmd.publish_data({"linear": {"x": 0.5}}))
            wait_until(lambda: odom and odom[-1] > 0.3, what="the robot driven past x = 0.3")
            graph.executor.post(lambda: cmd.publish_data({}))
            page.get_by_role("button", name="Reset").click()
            wait_until(
                lambda: abs(odom[-1]) < 0.05,
                what="the robot back at the origin",
                detail=lambda: odom[-1:],
            )
            page.get_by_text("Paused", exact=True).wait_for()
            page.get_by_role("button", name="Step").wait_for()
            docs_screenshot(page, "viewfix-arbotix-simulation")
    finally:
        runtime.close()
        graph.shutdown()


def _map_box(page: Any) -> tuple[int, int, int, int] | None:
    """The (left, top, width, height) of what is drawn over the 48 grey background, in the
    view but its left 80 px, where the axes gizmo is."""
    left = round(VIEW["x"]) + 80
    rgb = _screenshot(page)[:, left:].astype(int)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    drawn = (abs(r - 48) > 8) | (abs(g - 48) > 8) | (abs(b - 48) > 8)
    rows, cols = np.flatnonzero(drawn.any(axis=1)), np.flatnonzero(drawn.any(axis=0))
    if len(rows) == 0:
        return None
    return (
        left + int(cols[0]),
        int(rows[0]),
        int(cols[-1] - cols[0] + 1),
        int(rows[-1] - rows[0] + 1),
    )


def _show_the_cloister(
    config: str, seen: Callable[[tuple[int, int, int, int]], bool], picture: str | None = None
) -> None:
    """The course's 20 m cloister map in a viewer opened with ``config``, until ``seen`` holds
    for where the map is drawn (then the docs' ``picture`` of it, if named)."""
    from belvedere.maps import grid_message, load_map
    from belvedere.viewer import read_rviz

    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), rviz=read_rviz(DATA / config))
    grid = load_map(EXAMPLES / "mbot_navigation/maps/cloister_gmapping.yaml")
    pub = graph.create_node("map_server").publisher("/map", "nav_msgs/OccupancyGrid", latch=True)
    graph.start(rtf=None)
    graph.executor.post(lambda: pub.publish(grid_message(grid)))
    try:
        with browser_page(viewer.url) as page:
            wait_until(
                lambda: (box := _map_box(page)) is not None and seen(box),
                what=f"the map where {config} puts it",
                timeout=BROWSER_DEADLINE,
                detail=lambda: _map_box(page),
            )
            if picture:
                docs_screenshot(page, picture)
    finally:
        viewer.close()
        graph.shutdown()


def test_top_down_ortho_shows_the_map_at_the_files_scale() -> None:
    """A TopDownOrtho view as rviz writes it (Scale 25 px/m): the cloister's 20 m map is
    500 pixels across, seen from above."""

    def at_scale(box: tuple[int, int, int, int]) -> bool:
        return abs(box[2] - 500) <= 6 and abs(box[3] - 500) <= 6

    _show_the_cloister("course_gmapping.rviz", at_scale, "viewfix-topdown")


def test_the_courses_own_top_down_view_shows_the_map_with_x_up() -> None:
    """The course's gmapping.rviz looks straight down an XYOrbit yawed half a turn, 33.5 m
    from a focal point 10.4 m behind the origin: 25.2 px a metre (rviz's 45 degrees of
    view over 700 px), +x up the screen, so the map's x = -10 m edge lies 10 px above the
    view's middle row and the map runs off the top; it is 504 px across."""
    metre = 700 / (2 * 33.5 * math.tan(math.pi / 8))

    def placed(box: tuple[int, int, int, int]) -> bool:
        _, top, width, height = box
        bottom = top + height
        return abs(width - 20 * metre) <= 8 and top <= 2 and abs(bottom - (350 - 0.41 * metre)) <= 8

    _show_the_cloister("course_gmapping_xyorbit.rviz", placed)
