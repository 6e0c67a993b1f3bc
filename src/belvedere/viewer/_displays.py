"""Displays: each subscribes to one topic, keeps the latest message (cheap, on the executor)
and draws it on the render thread, placed by TF in the fixed frame."""

from __future__ import annotations

import threading
from collections import deque
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from belvedere.graph import Node
from belvedere.tf import TFBuffer, TFError, Transform, wxyz_from_xyzw

__all__ = ["DISPLAYS", "Display"]

F32 = npt.NDArray[np.float32]


def _arrow_segments(
    origin: npt.NDArray[np.float64], yaw_dir: npt.NDArray[np.float64], length: float
) -> F32:
    """Line segments of an arrow from ``origin`` along unit ``yaw_dir``."""
    tip = origin + yaw_dir * length
    side = np.array([-yaw_dir[1], yaw_dir[0], 0.0])
    back = tip - yaw_dir * length * 0.25
    return np.array(
        [[origin, tip], [tip, back + side * length * 0.12], [tip, back - side * length * 0.12]],
        dtype=np.float32,
    )


def _pose(p: Any) -> Transform:
    """A geometry_msgs/Pose (an all-zero quaternion, the message default, is identity)."""
    q = p.orientation
    xyzw = (q.x, q.y, q.z, q.w) if (q.x, q.y, q.z, q.w) != (0, 0, 0, 0) else (0.0, 0.0, 0.0, 1.0)
    return Transform((p.position.x, p.position.y, p.position.z), xyzw)


def _pose_parts(p: Any) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """(position, x-axis direction) of a geometry_msgs/Pose."""
    m = _pose(p).matrix()
    return m[:3, 3], m[:3, 0]


class Display:
    """One display: ``topic`` of ``msg_type``, drawn under ``/displays/<name>``."""

    kind: ClassVar[str] = ""
    msg_type: ClassVar[str] = ""

    def __init__(
        self, node: Node, scene: Any, gui: Any, name: str, topic: str, buffer: TFBuffer
    ) -> None:
        self.name = name
        self.topic = topic
        self.scene = scene
        self.gui = gui
        self.buffer = buffer
        self.latest: Any = None
        self.dirty = False
        self.lock = threading.Lock()
        self.handles: dict[str, Any] = {}
        self.frames: dict[str, Any] = {}
        self.enabled = True
        self.error: str | None = None
        self.subscription = node.subscribe(topic, self.msg_type, self.on_message, queue_size=1)

    def on_message(self, msg: Any) -> None:
        with self.lock:
            self.latest = msg
            self.dirty = True

    def frame_pose(self, frame_id: str, fixed: str) -> Transform | None:
        try:
            return self.buffer.lookup_transform(fixed, frame_id or fixed)
        except TFError as err:
            self.error = err.message
            return None

    def render(self, fixed: str) -> None:
        with self.lock:
            msg, self.dirty = self.latest, False
        if msg is not None and self.enabled:
            self.draw(msg, fixed)

    def draw(self, msg: Any, fixed: str) -> None:
        raise NotImplementedError

    def place(self, key: str, handle: Any, pose: Transform) -> None:
        """Keep ``handle`` (made under ``<base>/<key>/geom``) and put its frame at ``pose``.

        The pose goes on a parent frame node, updated like the robot's link frames."""
        frame = self.frames.get(key)
        if frame is None:
            frame = self.frames[key] = self.scene.add_frame(f"{self.base}/{key}", show_axes=False)
        frame.position = pose.translation
        frame.wxyz = wxyz_from_xyzw(pose.quat_xyzw)
        self.handles[key] = handle

    def remove(self) -> None:
        self.subscription.unregister()
        for h in (*self.handles.values(), *self.frames.values()):
            h.remove()
        self.handles.clear()
        self.frames.clear()

    @property
    def base(self) -> str:
        return f"/displays/{self.name}"


class LaserScanDisplay(Display):
    kind = "LaserScan"
    msg_type = "sensor_msgs/LaserScan"

    def draw(self, msg: Any, fixed: str) -> None:
        pose = self.frame_pose(msg.header.frame_id, fixed)
        if pose is None:
            return
        ranges = np.asarray(msg.ranges, dtype=np.float64)
        angles = msg.angle_min + np.arange(len(ranges)) * msg.angle_increment
        ok = np.isfinite(ranges) & (ranges >= msg.range_min) & (ranges <= msg.range_max)
        pts = np.stack(
            [ranges * np.cos(angles), ranges * np.sin(angles), np.zeros_like(ranges)], axis=1
        )[ok]
        if len(pts) == 0:
            pts = np.zeros((1, 3))
        h = self.scene.add_point_cloud(
            f"{self.base}/points/geom",
            pts.astype(np.float32),
            (255, 40, 40),
            point_size=0.03,
        )
        self.place("points", h, pose)


class PointCloud2Display(Display):
    kind = "PointCloud2"
    msg_type = "sensor_msgs/PointCloud2"

    def draw(self, msg: Any, fixed: str) -> None:
        pose = self.frame_pose(msg.header.frame_id, fixed)
        offsets = {f.name: f.offset for f in msg.fields}
        if pose is None or not {"x", "y", "z"} <= set(offsets):
            return
        data = np.frombuffer(bytes(msg.data), dtype=np.uint8).reshape(-1, msg.point_step)
        dtype = ">f4" if msg.is_bigendian else "<f4"
        pts = np.stack(
            [data[:, offsets[a] : offsets[a] + 4].copy().view(dtype)[:, 0] for a in "xyz"], axis=1
        )
        pts = pts[np.isfinite(pts).all(axis=1)]
        if len(pts) == 0:
            pts = np.zeros((1, 3), dtype=np.float32)
        h = self.scene.add_point_cloud(
            f"{self.base}/points/geom",
            pts.astype(np.float32),
            (40, 200, 255),
            point_size=0.02,
        )
        self.place("points", h, pose)


class OccupancyGridDisplay(Display):
    """A map (or costmap): redrawn when a new grid comes (a SLAM map grows), moved with its
    frame in between."""

    kind = "OccupancyGrid"
    msg_type = "nav_msgs/OccupancyGrid"
    scheme = "map"
    drawn: Any = None
    """The message the scene shows."""

    def draw(self, msg: Any, fixed: str) -> None:
        pose = self.frame_pose(msg.header.frame_id, fixed)
        info = msg.info
        if pose is None or info.width == 0 or info.height == 0:
            return
        if msg is self.drawn and "grid" in self.handles:
            self.place("grid", self.handles["grid"], pose @ _pose(info.origin))
            return
        grid = np.asarray(msg.data, dtype=np.int16).reshape(info.height, info.width)
        # Cells as square points (positions are exact; large maps are thinned to ~250k cells).
        stride = max(1, int(np.ceil(np.sqrt(grid.size / 250_000))))
        cells = grid[::stride, ::stride]
        colors = np.empty((*cells.shape, 3), dtype=np.uint8)
        if self.scheme == "costmap":
            t = np.clip(cells, 0, 100) / 100.0
            colors[..., 0] = (255 * t).astype(np.uint8)
            colors[..., 1] = (255 * (1 - t) * 0.6).astype(np.uint8)
            colors[..., 2] = (255 * (1 - t)).astype(np.uint8)
        else:
            colors[...] = (255 - np.clip(cells, 0, 100) * 255 // 100).astype(np.uint8)[..., None]
        colors[cells < 0] = (128, 128, 128)
        res = info.resolution * stride
        rows, cols = np.mgrid[0 : cells.shape[0], 0 : cells.shape[1]]
        pts = np.stack(
            [(cols + 0.5) * res, (rows + 0.5) * res, np.full(rows.shape, -0.002)], axis=-1
        )
        handle = self.scene.add_point_cloud(
            f"{self.base}/grid/geom",
            pts.reshape(-1, 3).astype(np.float32),
            colors.reshape(-1, 3),
            point_size=res,
            point_shape="square",
            point_shading="flat",
        )
        self.place("grid", handle, pose @ _pose(info.origin))
        self.drawn = msg


class CostmapDisplay(OccupancyGridDisplay):
    kind = "Costmap"
    scheme = "costmap"


class PoseStampedDisplay(Display):
    kind = "PoseStamped"
    msg_type = "geometry_msgs/PoseStamped"

    def draw(self, msg: Any, fixed: str) -> None:
        pose = self.frame_pose(msg.header.frame_id, fixed)
        if pose is None:
            return
        p, x = _pose_parts(msg.pose)
        h = self.scene.add_line_segments(
            f"{self.base}/arrow/geom",
            _arrow_segments(p, x, 0.5),
            (255, 0, 0),
            thickness=0.02,
        )
        self.place("arrow", h, pose)


class PoseArrayDisplay(Display):
    kind = "PoseArray"
    msg_type = "geometry_msgs/PoseArray"

    def draw(self, msg: Any, fixed: str) -> None:
        pose = self.frame_pose(msg.header.frame_id, fixed)
        if pose is None or not msg.poses:
            return
        segs = np.concatenate([_arrow_segments(*_pose_parts(p), 0.25) for p in msg.poses])
        h = self.scene.add_line_segments(
            f"{self.base}/arrows/geom", segs, (255, 80, 80), thickness=0.01
        )
        self.place("arrows", h, pose)


class PathDisplay(Display):
    kind = "Path"
    msg_type = "nav_msgs/Path"

    def draw(self, msg: Any, fixed: str) -> None:
        pose = self.frame_pose(msg.header.frame_id, fixed)
        if pose is None or len(msg.poses) < 2:
            return
        pts = np.array(
            [[p.pose.position.x, p.pose.position.y, p.pose.position.z] for p in msg.poses]
        )
        segs = np.stack([pts[:-1], pts[1:]], axis=1).astype(np.float32)
        h = self.scene.add_line_segments(
            f"{self.base}/path/geom", segs, (0, 200, 0), thickness=0.02
        )
        self.place("path", h, pose)


class OdometryDisplay(Display):
    kind = "Odometry"
    msg_type = "nav_msgs/Odometry"

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.trail: deque[F32] = deque(maxlen=100)

    def draw(self, msg: Any, fixed: str) -> None:
        pose = self.frame_pose(msg.header.frame_id, fixed)
        if pose is None:
            return
        p, x = _pose_parts(msg.pose.pose)
        if not self.trail or np.linalg.norm(self.trail[-1][0] - p) > 0.1:
            self.trail.append(_arrow_segments(p, x, 0.3))
        segs = np.concatenate(list(self.trail)).astype(np.float32)
        h = self.scene.add_line_segments(
            f"{self.base}/arrows/geom", segs, (255, 30, 30), thickness=0.01
        )
        self.place("arrows", h, pose)


class MarkerDisplay(Display):
    kind = "Marker"
    msg_type = "visualization_msgs/Marker"

    def draw(self, msg: Any, fixed: str) -> None:
        self.draw_marker(msg, fixed)

    def draw_marker(self, m: Any, fixed: str) -> None:
        key = f"{m.ns}_{m.id}"
        if m.action in (2, 3):  # DELETE, DELETEALL
            for k in [k for k in self.handles if m.action == 3 or k == key]:
                self.handles.pop(k).remove()
                self.frames.pop(k).remove()
            return
        pose = self.frame_pose(m.header.frame_id, fixed)
        if pose is None:
            return
        local = _pose(m.pose)
        where = pose @ local
        color = (round(m.color.r * 255), round(m.color.g * 255), round(m.color.b * 255))
        opacity = m.color.a if m.color.a < 1 else None
        name = f"{self.base}/{key}/geom"
        s = (m.scale.x, m.scale.y, m.scale.z)
        if m.type == 1:
            h = self.scene.add_box(name, color=color, dimensions=s, opacity=opacity)
        elif m.type == 2:
            h = self.scene.add_icosphere(name, radius=max(s) / 2, color=color, opacity=opacity)
        elif m.type == 3:
            h = self.scene.add_cylinder(
                name, radius=s[0] / 2, height=s[2], color=color, opacity=opacity
            )
        elif m.type in (4, 5, 8) and m.points:
            pts = np.array([[p.x, p.y, p.z] for p in m.points], dtype=np.float32)
            if m.type == 8:
                h = self.scene.add_point_cloud(name, pts, color, point_size=max(s[0], 0.01))
            else:
                segs = (
                    np.stack([pts[:-1], pts[1:]], axis=1)
                    if m.type == 4
                    else pts[: len(pts) // 2 * 2].reshape(-1, 2, 3)
                )
                h = self.scene.add_line_segments(name, segs, color, thickness=max(s[0], 0.005))
        elif m.type == 9:
            h = self.scene.add_label(name, m.text)
        elif m.type == 0:
            h = self.scene.add_line_segments(
                name,
                _arrow_segments(np.zeros(3), np.array([1.0, 0, 0]), max(s[0], 0.1)),
                color,
                thickness=max(s[1], 0.01),
            )
        else:
            return
        self.place(key, h, where)


class MarkerArrayDisplay(MarkerDisplay):
    kind = "MarkerArray"
    msg_type = "visualization_msgs/MarkerArray"

    def draw(self, msg: Any, fixed: str) -> None:
        for m in msg.markers:
            self.draw_marker(m, fixed)


class ImageDisplay(Display):
    kind = "Image"
    msg_type = "sensor_msgs/Image"

    def draw(self, msg: Any, fixed: str) -> None:
        data = np.frombuffer(bytes(msg.data), dtype=np.uint8)
        enc = msg.encoding.lower()
        if enc in ("rgb8", "bgr8"):
            image = data.reshape(msg.height, msg.step)[:, : msg.width * 3].reshape(
                msg.height, msg.width, 3
            )
            if enc == "bgr8":
                image = image[..., ::-1]
        elif enc in ("mono8", "8uc1"):
            image = np.repeat(data.reshape(msg.height, msg.step)[:, : msg.width, None], 3, axis=2)
        else:
            self.error = f"image encoding {msg.encoding!r} is not shown (rgb8, bgr8, mono8 are)"
            return
        handle = self.handles.get("panel")
        if handle is None:
            self.handles["panel"] = self.gui.add_image(np.ascontiguousarray(image), label=self.name)
        else:
            handle.image = np.ascontiguousarray(image)


class CameraDisplay(ImageDisplay):
    kind = "Camera"


DISPLAYS: dict[str, type[Display]] = {
    d.kind: d
    for d in (
        LaserScanDisplay,
        PointCloud2Display,
        OccupancyGridDisplay,
        CostmapDisplay,
        OdometryDisplay,
        PathDisplay,
        PoseStampedDisplay,
        PoseArrayDisplay,
        MarkerDisplay,
        MarkerArrayDisplay,
        ImageDisplay,
        CameraDisplay,
    )
}
