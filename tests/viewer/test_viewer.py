"""Viewer parts that need no browser: mesh-path guard, rviz configs, floor clicks, CLI errors,
the Map display's updates."""

from __future__ import annotations

import json
import socket
import struct
import time
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from belvedere.cli import main
from belvedere.graph import Graph
from belvedere.maps import OccupancyMap, grid_message
from belvedere.msgs import message_from_data
from belvedere.packages import PackageIndex
from belvedere.tf import TFBuffer, Transform
from belvedere.viewer import (
    MeshAccessError,
    Viewer,
    allowed_mesh_path,
    floor_point,
)
from tests.conftest import EXAMPLES
from tests.waiting import wait_until

PKG = EXAMPLES / "mbot_description"


@pytest.mark.parametrize(
    "filename",
    [
        "package://mbot_description/../../../etc/passwd",
        "/etc/passwd",
        "file:///etc/hostname",
        "../../../../etc/passwd",
    ],
)
def test_meshes_outside_package_roots_are_refused(filename: str) -> None:
    packages = PackageIndex([EXAMPLES])
    model = PKG / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"
    with pytest.raises(MeshAccessError, match="outside the package roots; refused"):
        allowed_mesh_path(filename, model_path=str(model), packages=packages, at=None)


def test_meshes_inside_package_roots_resolve() -> None:
    packages = PackageIndex([EXAMPLES])
    path = allowed_mesh_path(
        "package://mbot_description/meshes/kinect.dae", model_path=None, packages=packages, at=None
    )
    assert path == (PKG / "meshes" / "kinect.dae").resolve()


def test_floor_point() -> None:
    assert floor_point((0.0, 0.0, 2.0), (0.5, 0.0, -1.0)) == (1.0, 0.0)
    assert floor_point((0.0, 0.0, 2.0), (0.0, 0.0, 1.0)) is None
    assert floor_point((0.0, 0.0, 2.0), (1.0, 0.0, 0.0)) is None


def test_display_of_a_broken_model_is_an_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.urdf"
    bad.write_text('<robot name="r"><link name="a"/><link name="b"/></robot>')
    assert main(["display", str(bad), "--port", "0"]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{bad}:1:1: error: two root links found")


def glb_lines(data: bytes) -> npt.NDArray[np.float32]:
    """The line segments (N, 2, 3) of a GLB holding one primitive in LINES mode."""
    text_length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20 : 20 + text_length])
    blob = data[20 + text_length + 8 :]
    (primitive,) = document["meshes"][0]["primitives"]
    assert primitive["mode"] == 1  # GL_LINES: a pixel wide whatever the distance
    accessor = document["accessors"][primitive["attributes"]["POSITION"]]
    view = document["bufferViews"][accessor["bufferView"]]
    points = np.frombuffer(blob, np.float32, accessor["count"] * 3, view["byteOffset"])
    return points.reshape(-1, 2, 3)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


@pytest.mark.parametrize(
    ("values", "lines", "normal_axis"),
    [
        ({}, 22, 2),  # rviz's default: 10 x 10 cells of 1 m in XY
        ({"Plane Cell Count": 4, "Cell Size": 0.5, "Plane": "XZ"}, 10, 1),
        ({"Plane Cell Count": 2, "Normal Cell Count": 2, "Plane": "YZ"}, 3 * 6 + 9, 0),
    ],
)
def test_grid_is_rviz_lines(values: dict[str, object], lines: int, normal_axis: int) -> None:
    """The Grid display draws rviz's lines (cell count + 1 each way, a level per normal cell,
    verticals joining them) in the chosen plane, centred on the offset."""
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="map")
    try:
        grid = viewer.add_display("Grid", values={**values, "X": 1.0, "Y": -2.0, "Z": 0.5})
        segs = grid.segments()  # type: ignore[attr-defined]
        assert segs.shape == (lines, 2, 3)
        cells = int(values.get("Plane Cell Count", 10))  # type: ignore[call-overload]
        size = float(values.get("Cell Size", 1.0))  # type: ignore[arg-type]
        offset = np.array([1.0, -2.0, 0.5])
        spread = segs.reshape(-1, 3) - offset
        in_plane = [a for a in range(3) if a != normal_axis]
        for axis in in_plane:
            assert spread[:, axis].min() == pytest.approx(-cells * size / 2)
            assert spread[:, axis].max() == pytest.approx(cells * size / 2)
        normal = int(values.get("Normal Cell Count", 0))  # type: ignore[call-overload]
        assert np.abs(spread[:, normal_axis]).max() == pytest.approx(normal * size / 2)
        viewer.render_once()
        pieces = grid.pieces()  # type: ignore[attr-defined]
        drawn = glb_lines(grid.handles["grid"].glb_data)
        assert np.array_equal(drawn, pieces)
        # the lines come in pieces a cell long at most, and in all cover the lines end to end
        lengths = np.linalg.norm(pieces[:, 1] - pieces[:, 0], axis=1)
        assert lengths.max() == pytest.approx(size, rel=1e-5)
        assert lengths.sum() == pytest.approx(
            np.linalg.norm(segs[:, 1] - segs[:, 0], axis=1).sum(), rel=1e-5
        )
    finally:
        viewer.close()
        graph.shutdown()


@pytest.mark.parametrize(
    ("display_type", "values", "message", "style"),
    [
        ("Path", {}, {"poses": [{}, {"pose": {"position": {"x": 1.0}}}]}, ("screen", 1.5)),
        (
            "Path",
            {"Line Style": "Billboards", "Line Width": 0.05},
            {"poses": [{}, {"pose": {"position": {"x": 1.0}}}]},
            ("world", 0.05),
        ),
        ("Polygon", {}, {"polygon": {"points": [{}, {"x": 1.0}, {"y": 1.0}]}}, ("screen", 1.5)),
        ("PoseArray", {}, {"poses": [{"orientation": {"w": 1.0}}]}, ("screen", 1.5)),
        (
            "PoseArray",
            {"Shape": "Arrow (3D)"},
            {"poses": [{"orientation": {"w": 1.0}}]},
            ("world", 0.01),
        ),
    ],
)
def test_lines_are_a_pixel_wide_unless_billboards(
    display_type: str,
    values: dict[str, object],
    message: dict[str, object],
    style: tuple[str, float],
) -> None:
    """rviz draws a Path's "Lines", a footprint and flat particle arrows a pixel wide on screen,
    a Path's "Billboards" ``Line Width`` metres wide (and its 3D arrows as solids)."""
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="map")
    try:
        display = viewer.add_display(display_type, values=values)
        msg = message_from_data(display.msg_type, {"header": {"frame_id": "map"}, **message})
        display.draw(msg, Transform())
        handle = display.handles["lines"]
        assert handle.thickness_units == style[0]
        assert handle.thickness == pytest.approx(style[1])
    finally:
        viewer.close()
        graph.shutdown()


def test_a_drawn_path_takes_a_new_line_style_and_colour_at_once() -> None:
    """A latched plan is not sent again: rviz redraws it when its properties change."""
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="map")
    try:
        display = viewer.add_display("Path")
        poses = [{}, {"pose": {"position": {"x": 1.0}}}]
        msg = message_from_data(display.msg_type, {"header": {"frame_id": "map"}, "poses": poses})
        display.draw(msg, Transform())
        display.set_value("Line Style", "Billboards")
        display.set_value("Color", (0, 0, 255))
        handle = display.handles["lines"]
        assert (handle.thickness_units, handle.thickness) == ("world", 0.03)
        assert np.asarray(handle.colors).reshape(-1).tolist() == [0, 0, 255]
        assert np.asarray(handle.points).shape == (1, 2, 3)
    finally:
        viewer.close()
        graph.shutdown()


def test_a_new_scan_moves_the_points_of_the_same_cloud() -> None:
    """Each scan's points go into the one point cloud the display made (a new scene node per
    scan makes the browser build a new material each time); a style change makes a new one."""
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="laser")
    try:
        display = viewer.add_display("LaserScan", "/scan")
        pub = graph.create_node("lidar").publisher("/scan", "sensor_msgs/LaserScan")
        graph.start(rtf=None)

        def scan(r: float) -> None:
            graph.executor.post(
                lambda: pub.publish_data(
                    {
                        "header": {"frame_id": "laser"},
                        "angle_min": 0.0,
                        "angle_increment": 0.5,
                        "range_max": 10.0,
                        "ranges": [r] * 4,
                    }
                )
            )

        def drawn_x() -> float:
            handle = display.handles.get("points")
            return float(handle.points[0, 0]) if handle is not None else 0.0

        scan(1.0)
        wait_until(lambda: drawn_x() == 1.0, what="the first scan drawn")
        handle = display.handles["points"]
        scan(2.0)
        wait_until(lambda: drawn_x() == 2.0, what="the second scan drawn")
        assert display.handles["points"] is handle
        assert handle.points.shape == (4, 3)
        # rviz's 0.01 m default squares: viser draws a point of size s about 2 s wide
        assert handle.point_size == pytest.approx(0.01 / 2)
        assert np.asarray(handle.colors).reshape(-1).tolist() == [255, 0, 0]  # rviz's flat red
        display.set_value("Style", "Points")
        scan(3.0)
        wait_until(lambda: drawn_x() == 3.0, what="the third scan drawn")
        assert display.handles["points"] is not handle
    finally:
        viewer.close()
        graph.shutdown()


def test_a_growing_map_is_redrawn_as_it_grows() -> None:
    """The Map display shows the latest /map: a SLAM map that grows is drawn again (and a
    map that does not change is not rebuilt every frame)."""
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="map")
    try:
        display = viewer.add_display("OccupancyGrid", "/map")
        pub = graph.create_node("slam").publisher("/map", "nav_msgs/OccupancyGrid", latch=True)
        graph.start(rtf=None)

        def width() -> int:
            drawn = getattr(display, "drawn", None)
            return int(drawn.info.width) if drawn is not None else 0

        small = grid_message(OccupancyMap(np.zeros((4, 5), np.int8), 0.05))
        graph.executor.post(lambda: pub.publish(small))
        wait_until(lambda: width() == 5, what="the 5-cell-wide map drawn")
        handle = display.handles["grid"]
        image = getattr(display, "image", None)
        assert image is not None
        assert image.shape == (4, 5, 4)
        assert (image[..., :3] == 255).all()  # free: white
        assert (image[..., 3] == round(0.7 * 255)).all()  # rviz's Map alpha 0.7
        frames = viewer.frames_rendered
        wait_until(lambda: viewer.frames_rendered > frames + 2, what="more frames")
        assert display.handles["grid"] is handle  # the same map: not rebuilt
        bigger = grid_message(OccupancyMap(np.full((8, 10), 100, np.int8), 0.05))
        graph.executor.post(lambda: pub.publish(bigger))
        wait_until(lambda: width() == 10, what="the grown map drawn")
        assert display.handles["grid"] is not handle
        image = getattr(display, "image", None)
        assert image is not None
        assert image.shape == (8, 10, 4)
        assert (image[..., :3] == 0).all()  # occupied: black
    finally:
        viewer.close()
        graph.shutdown()


def test_markers_expire_follow_locked_frames_and_are_deleted() -> None:
    """A Marker with a lifetime goes when it is over (graph time, from its arrival); a
    frame_locked one moves with its frame; DELETE removes one (rviz's rules)."""
    graph = Graph(sim_time=True)
    viewer = Viewer(graph, port=free_port(), fixed_frame="map")
    try:
        display = viewer.add_display("Marker", "/visualization_marker")
        node = graph.create_node("markers")
        pub = node.publisher("/visualization_marker", "visualization_msgs/Marker")
        tf = node.publisher("/tf", "tf2_msgs/TFMessage")

        def base_at(x: float) -> None:
            now = node.now_ns()
            tf.publish_data(
                {
                    "transforms": [
                        {
                            "header": {"frame_id": "map", "stamp": [now // 10**9, now % 10**9]},
                            "child_frame_id": "base",
                            "transform": {"translation": {"x": x}, "rotation": {"w": 1.0}},
                        }
                    ]
                }
            )

        def marker(ident: int, **fields: object) -> None:
            now = node.now_ns()
            pub.publish_data(
                {
                    "header": {"frame_id": "base", "stamp": [now // 10**9, now % 10**9]},
                    "ns": "n",
                    "id": ident,
                    "type": 1,
                    "scale": {"x": 0.1, "y": 0.1, "z": 0.1},
                    "color": {"r": 1.0, "a": 1.0},
                    "pose": {"position": {"y": 0.5}, "orientation": {"w": 1.0}},
                    **fields,
                }
            )

        def at(key: str) -> tuple[float, ...]:
            handle = display.handles.get(key)
            return tuple(handle.position) if handle is not None else ()

        base_at(1.0)
        graph.run(duration=0.1)
        marker(1, lifetime={"sec": 1})
        marker(2, frame_locked=True)
        marker(3)
        base_at(1.0)  # a transform after their stamp: the message filter lets them through
        graph.run(duration=0.1)
        # (the viewer's render thread draws them)
        wait_until(lambda: {"n/1", "n/2", "n/3"} <= set(display.handles), what="3 markers")
        wait_until(lambda: at("n/2") == pytest.approx((1.0, 0.5, 0.0)), what="n/2 at x = 1")
        base_at(3.0)
        graph.run(duration=1.2)
        base_at(3.0)  # past the first marker's lifetime
        wait_until(lambda: "n/1" not in display.handles, what="n/1 gone after its lifetime")
        wait_until(lambda: at("n/2") == pytest.approx((3.0, 0.5, 0.0)), what="n/2 moved along")
        assert at("n/3") == pytest.approx((1.0, 0.5, 0.0))  # not locked: stays
        marker(3, action=2)
        graph.run(duration=0.1)
        wait_until(lambda: "n/3" not in display.handles, what="n/3 deleted")
    finally:
        viewer.close()
        graph.shutdown()


def test_tf_hides_a_frame_that_stopped_after_frame_timeout() -> None:
    """rviz's Frame Timeout: a frame whose transform stopped coming is not drawn once the
    timeout has passed; a static frame stays."""
    graph = Graph(sim_time=True)
    viewer = Viewer(graph, port=free_port(), fixed_frame="map")
    try:
        tf_display = viewer.add_display("TF", values={"Frame Timeout": 2.0})
        node = graph.create_node("frames")
        tf = node.publisher("/tf", "tf2_msgs/TFMessage")
        static = node.publisher("/tf_static", "tf2_msgs/TFMessage", latch=True)

        def transform(child: str) -> dict[str, object]:
            now = node.now_ns()
            return {
                "header": {"frame_id": "map", "stamp": [now // 10**9, now % 10**9]},
                "child_frame_id": child,
                "transform": {"translation": {"x": 1.0}, "rotation": {"w": 1.0}},
            }

        static.publish_data({"transforms": [transform("fixed")]})
        ticker = node.timer(0.1, lambda: tf.publish_data({"transforms": [transform("moving")]}))
        graph.run(duration=1.0)

        def shown(frame: str) -> bool:
            handle = tf_display.handles.get(f"frame:{frame}")
            return handle is not None and bool(handle.visible)

        wait_until(lambda: shown("moving") and shown("fixed"), what="both frames drawn")
        ticker.cancel()
        graph.run(duration=3.0)  # past the timeout
        wait_until(lambda: not shown("moving"), what="the stopped frame hidden")
        assert shown("fixed")
    finally:
        viewer.close()
        graph.shutdown()


def test_changing_a_property_while_frames_are_drawn_never_breaks_a_frame() -> None:
    """The panel's threads change a display while the render thread draws it: a style
    change takes the cloud apart between frames, never under one (which wrote to a removed
    scene node and put the display in Error)."""
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=free_port(), fixed_frame="laser")
    try:
        display = viewer.add_display("LaserScan", "/scan")
        pub = graph.create_node("lidar").publisher("/scan", "sensor_msgs/LaserScan")
        ranges = {"angle_increment": 0.01, "range_max": 10.0, "ranges": [1.0] * 360}
        graph.create_node("clock").timer(
            0.005, lambda: pub.publish_data({"header": {"frame_id": "laser"}, **ranges})
        )
        graph.start(rtf=None)
        wait_until(lambda: "points" in display.handles, what="the first scan drawn")
        frames = viewer.frames_rendered
        for i in range(300):  # over some tens of frames
            display.set_value("Style", "Points" if i % 2 else "Flat Squares")
            time.sleep(0.002)
        wait_until(lambda: viewer.frames_rendered > frames + 3, what="more frames")
        assert display.status.get("Display") is None
    finally:
        viewer.close()
        graph.shutdown()


class _Camera:
    """The state a browser tab's camera reports back (viser's ``client.camera``)."""

    def __init__(self) -> None:
        self.position = np.zeros(3)
        self.look_at = np.zeros(3)
        self.up_direction = np.array([0.0, 0.0, 1.0])
        self.fov = 1.0
        self.near = 0.01
        self.far = 1000.0
        self.image_height = 700


class _Following:
    """An Orbit view following frame ``base`` in ``odom`` into a :class:`_Camera`, on a clock
    the test moves."""

    def __init__(self, camera: _Camera | None = None) -> None:
        from belvedere.viewer._views import ViewState

        self.buffer = TFBuffer()
        self.camera = camera or _Camera()
        self.now = 0.0
        self.view = ViewState(
            "rviz/Orbit", {"Distance": 3.0, "Target Frame": "base"}, clock=lambda: self.now
        )
        self._stamp = 0

    def frame(self, base_x: float | None = None) -> None:
        """One frame of the view, the base first moved to ``base_x`` if given."""
        if base_x is not None:
            self._stamp += 1
            self.buffer.set_transform("odom", "base", Transform((base_x, 0.0, 0.0)), self._stamp)
        self.view.follow(self.camera, self.buffer, "odom")

    def seen(self) -> tuple[Any, Any]:
        return (np.array(self.camera.position, dtype=float), np.array(self.camera.look_at, float))

    def offset(self) -> Any:
        return np.asarray(self.camera.look_at) - np.asarray(self.camera.position)


def test_a_followed_view_keeps_its_offset_through_a_report_between_eye_and_target() -> None:
    """The eye and the target reach the browser as two messages: a camera report made
    between them (a new eye, the older target) is not the user's mouse, and the view keeps
    following with the offset it had; a camera the user moved follows from where it was put."""
    f = _Following()
    f.frame(0.0)
    first = f.offset()
    target0 = f.seen()[1]
    f.frame(0.1)
    f.camera.look_at = target0  # reported before the new target came
    f.frame(0.2)
    assert f.camera.look_at[0] == pytest.approx(target0[0] + 0.2)
    assert f.offset() == pytest.approx(first)
    f.camera.position = np.asarray(f.camera.position) + np.array([0.0, 0.0, 1.0])  # the mouse
    f.frame(0.3)  # the camera stays where the user put it
    assert f.camera.look_at[0] == pytest.approx(target0[0] + 0.2)
    f.frame(0.4)  # and moves along from there
    assert f.camera.look_at[0] == pytest.approx(target0[0] + 0.3)
    assert f.offset() == pytest.approx(first - np.array([0.0, 0.0, 1.0]))


def test_a_followed_view_tells_a_tab_again_that_reports_an_older_camera() -> None:
    """A tab whose report stays on an older camera it was told (its report of the newest one
    lost in a race) is told the newest again after a second, not left behind for good."""
    from belvedere.viewer._views import RESEND_S

    f = _Following()
    f.frame(1.45)
    older = f.seen()
    f.frame(1.5)
    f.camera.position, f.camera.look_at = older  # the tab's last report: the older camera
    f.frame()  # the robot has stopped
    assert f.camera.look_at[0] == pytest.approx(1.45)  # a report may lag: no resend at once
    f.now += RESEND_S
    f.frame()
    assert f.camera.look_at[0] == pytest.approx(1.5)
    f.camera.position = np.asarray(f.camera.position) + np.array([0.0, 0.0, 1.0])  # the mouse
    f.now += 2 * RESEND_S
    f.frame()
    assert f.camera.position[2] == pytest.approx(older[0][2] + 1.0)  # the user's camera stays


def test_a_followed_view_keeps_its_offset_through_a_target_it_never_told() -> None:
    """viser's position setter sends a target moved with the eye from the camera it last heard
    of before the target the view sets: a report of a told eye with that target is not the
    user's mouse."""
    f = _Following()
    f.frame(1.45)
    first = f.offset()
    f.frame(1.5)
    f.camera.look_at = np.asarray(f.camera.look_at) - np.array([0.02, 0.0, 0.0])  # never told
    f.frame()
    f.frame(1.6)
    assert f.camera.look_at[0] == pytest.approx(1.6)
    assert f.offset() == pytest.approx(first)


def test_a_placed_view_is_not_undone_by_a_report_of_the_camera_before_it() -> None:
    """The tab may report the camera it had before the view placed it (the previous view's)
    after the placement: that is not the user's mouse. Once it has reported a camera it was
    told, a camera it was not told is the user's."""
    camera = _Camera()
    camera.position, camera.look_at = np.array([3.0, 0.5, 2.0]), np.array([0.0, 0.0, 0.1])
    before = (camera.position, camera.look_at)
    f = _Following(camera)
    f.frame(0.0)
    placed = f.offset()
    camera.position, camera.look_at = before  # a late report
    f.frame(0.5)
    assert f.offset() == pytest.approx(placed)
    assert camera.look_at[0] == pytest.approx(0.5)
    f.frame()  # the tab reports a told camera
    camera.position, camera.look_at = before  # now it is the user's
    f.frame()
    assert camera.position == pytest.approx(before[0])


def test_a_followed_view_puts_back_a_tab_that_went_back_to_the_initial_camera() -> None:
    """viser's client may move a tab back to the initial camera after a view has placed it
    (the view once followed from there, 5 cm behind a stopped robot): the view puts it back,
    after a second when the target stands still."""
    from belvedere.viewer._views import CAMERA_LOOK_AT, CAMERA_POSITION, RESEND_S

    f = _Following()
    f.frame(0.5)
    placed = f.seen()
    f.frame()  # told: synced
    f.camera.position, f.camera.look_at = np.array(CAMERA_POSITION), np.array(CAMERA_LOOK_AT)
    f.now += RESEND_S
    f.frame()
    assert f.seen()[0] == pytest.approx(placed[0])
    assert f.seen()[1] == pytest.approx(placed[1])


def test_a_followed_view_puts_back_a_tab_that_reports_the_clients_own_default_camera() -> None:
    """A loaded tab may report viser's client's own initial camera (3, 3, 3), from before the
    server's initial camera reached it, after the view placed it and the tab had reported
    that: not the user's mouse (a TopDownOrtho view followed from there showed one robot
    filling the view); the view puts it back."""
    from belvedere.viewer._views import CLIENT_DEFAULT_POSITION, RESEND_S

    f = _Following()
    f.frame(0.5)
    placed = f.seen()
    f.frame()  # told: synced
    f.camera.position, f.camera.look_at = np.array(CLIENT_DEFAULT_POSITION), np.zeros(3)
    f.frame()
    assert not f.view.moved
    f.now += RESEND_S
    f.frame()
    assert f.seen()[0] == pytest.approx(placed[0])
    assert f.seen()[1] == pytest.approx(placed[1])


def test_a_top_down_view_is_placed_again_for_a_canvas_reported_late() -> None:
    """A tab may first report its canvas unsized (150 px high): the TopDownOrtho view placed
    for that would show a twentieth of the map's scale; it is placed again for the canvas's
    real height, not for the lower pixel ratio viser takes under load, and never after the
    user moved the camera."""
    from belvedere.viewer._views import ViewState

    camera = _Camera()
    camera.image_height = 150
    view = ViewState("rviz/TopDownOrtho", {"Scale": 25.0})
    buffer = TFBuffer()

    def height() -> float:
        view.follow(camera, buffer, "map")
        return float(np.asarray(camera.position)[2])

    early = height()
    camera.image_height = 700
    placed = height()
    assert placed == pytest.approx(early * 700 / 150)
    camera.image_height = 525  # viser's pixel ratio at 0.75
    assert height() == pytest.approx(placed)
    camera.image_height = 700
    height()  # the tab reports the told camera
    camera.position = np.asarray(camera.position) * np.array([1.0, 1.0, 0.5])  # the mouse
    height()
    camera.image_height = 1400
    assert height() == pytest.approx(placed * 0.5)
