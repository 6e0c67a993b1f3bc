"""Displays of poses and shapes: Odometry, Path, Pose, PoseArray, Polygon, PointStamped, Marker
and MarkerArray — each drawn in the fixed frame with the transform at its stamp."""

from __future__ import annotations

from collections import deque
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.graph import NS
from belvedere.tf import Transform, wxyz_from_xyzw
from belvedere.viewer._covariance import POSITION_STYLE, YAW_STYLE, position_ellipsoids, yaw_fans
from belvedere.viewer._display import Display, Prop, line_style, transform_points
from belvedere.viewer._displays import msg_pose

__all__ = [
    "MarkerArrayDisplay",
    "MarkerDisplay",
    "OdometryDisplay",
    "PathDisplay",
    "PointStampedDisplay",
    "PolygonDisplay",
    "PoseArrayDisplay",
    "PoseDisplay",
]

F32 = npt.NDArray[np.float32]


def arrow_segments(pose: Transform, length: float) -> F32:
    """Line segments of a flat arrow along ``pose``'s x axis, in the frame ``pose`` is in."""
    m = pose.matrix()
    origin, along, side = m[:3, 3], m[:3, 0], m[:3, 1]
    tip = origin + along * length
    back = tip - along * length * 0.25
    return np.array(
        [[origin, tip], [tip, back + side * length * 0.12], [tip, back - side * length * 0.12]],
        dtype=np.float32,
    )


_ARROW = (
    Prop("Color", (255, 25, 0), "color"),
    Prop("Alpha", 1.0, "float"),
    Prop("Shape", "Arrow", "choice", ("Arrow", "Axes")),
    Prop("Shaft Length", 1.0, "float", low=0.01, high=5.0),
)


class _Segments(Display):
    """Shapes made of line segments, all in one scene node per display."""

    shown: F32 | None = None
    """The segments drawn last, in the fixed frame."""

    def line(self) -> dict[str, Any]:
        """viser's line thickness: arrows drawn as rviz's 3D ones are a centimetre thick."""
        return {"thickness": 0.01}

    def changed(self, key: str) -> None:
        # rviz redraws a latched path in its new colour or line style at once
        if self.shown is not None and "lines" in self.handles:
            self.show_segments(self.shown)

    def show_segments(self, segments: F32) -> None:
        self.shown = segments
        if len(segments) == 0:
            self.forget("lines")
            return
        handle = self.ctx.scene.add_line_segments(
            f"{self.base}/lines",
            segments.astype(np.float32),
            tuple(self.values["Color"]),
            **self.line(),
        )
        self.keep("lines", handle)


class OdometryDisplay(Display):
    """Solid arrows (or axes) of the last Keep poses, a new one when the robot moved past the
    tolerances, each with its covariance (rviz's defaults: shown)."""

    cls = "rviz/Odometry"
    type_name = "Odometry"
    msg_type = "nav_msgs/Odometry"
    default_topic = "/odom"
    props = (
        Prop("Shape", "Arrow", "choice", ("Arrow", "Axes")),
        Prop("Color", (255, 25, 0), "color"),
        Prop("Alpha", 1.0, "float"),
        Prop("Shaft Length", 1.0, "float", low=0.01, high=5.0),
        Prop("Shaft Radius", 0.05, "float", low=0.001, high=1.0),
        Prop("Head Length", 0.3, "float", low=0.001, high=1.0),
        Prop("Head Radius", 0.1, "float", low=0.001, high=1.0),
        Prop("Axes Length", 1.0, "float", low=0.01, high=5.0),
        Prop("Axes Radius", 0.1, "float", low=0.001, high=1.0),
        Prop("Covariance", True, "bool"),
        Prop("Position", True, "bool"),
        Prop("Orientation", True, "bool"),
        Prop("Position Tolerance", 0.1, "float", low=0.0, high=5.0),
        Prop("Angle Tolerance", 0.1, "float", low=0.0, high=3.14),
        Prop("Keep", 100, "int", low=1, high=10000, step=1),
    )

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.trail: deque[tuple[Transform, tuple[float, ...]]] = deque()
        """Each kept pose in the fixed frame, with its covariance in that frame's axes."""
        super().__init__(*args, **kwargs)

    def draw(self, msg: Any, pose: Transform) -> None:
        here = pose @ msg_pose(msg.pose.pose)
        if self.trail:
            last = self.trail[-1][0]
            moved = float(np.linalg.norm(np.subtract(here.translation, last.translation)))
            dq = abs(float(np.dot(here.quat_xyzw, last.quat_xyzw)))
            turned = 2 * float(np.arccos(min(1.0, dq)))
            if moved < float(self.values["Position Tolerance"]) and turned < float(
                self.values["Angle Tolerance"]
            ):
                return
        # the covariance is in the message's frame: seen from the fixed frame, turned by it
        self.trail.append((here, tuple(float(v) for v in msg.pose.covariance)))
        while len(self.trail) > max(1, int(self.values["Keep"])):
            self.trail.popleft()
        self.redraw()

    def redraw(self) -> None:
        poses = [p for p, _ in self.trail]
        if self.values["Shape"] == "Axes":
            self.forget("arrows")
            self.keep("axes", self._axes(poses))
        else:
            self.forget("axes")
            self.keep("arrows", self._arrows(poses))
        self._covariance()

    def _arrows(self, poses: list[Transform]) -> Any:
        shaft, head = float(self.values["Shaft Length"]), float(self.values["Head Length"])
        ends = np.array(
            [[p.translation, p.matrix()[:3, :3] @ (shaft + head, 0.0, 0.0) + p.translation]
             for p in poses]
        )  # fmt: skip
        return self.ctx.scene.add_arrows(
            f"{self.base}/arrows",
            ends.astype(np.float32),
            tuple(self.values["Color"]),
            shaft_radius=float(self.values["Shaft Radius"]),
            head_radius=float(self.values["Head Radius"]),
            head_length=head,
        )

    def _axes(self, poses: list[Transform]) -> Any:
        return self.ctx.scene.add_batched_axes(
            f"{self.base}/axes",
            batched_wxyzs=np.array([wxyz_from_xyzw(p.quat_xyzw) for p in poses]),
            batched_positions=np.array([p.translation for p in poses]),
            axes_length=float(self.values["Axes Length"]),
            axes_radius=float(self.values["Axes Radius"]),
        )

    def _covariance(self) -> None:
        shown = bool(self.values["Covariance"])
        for key, wanted, mesh, (colour, alpha) in (
            ("position", shown and self.values["Position"], position_ellipsoids, POSITION_STYLE),
            ("orientation", shown and self.values["Orientation"], yaw_fans, YAW_STYLE),
        ):
            made = mesh(list(self.trail)) if wanted else None
            if made is None:
                self.forget(key)
                continue
            handle = self.ctx.scene.add_mesh_simple(
                f"{self.base}/{key}", made[0], made[1], color=colour, opacity=alpha,
                side="double", cast_shadow=False, receive_shadow=False,
            )  # fmt: skip
            self.keep(key, handle)

    def changed(self, key: str) -> None:
        if self.trail and self.handles:
            self.redraw()  # rviz redraws the kept poses in the new shape or colour at once

    def reset(self) -> None:
        self.trail.clear()
        super().reset()


class PathDisplay(_Segments):
    cls = "rviz/Path"
    type_name = "Path"
    msg_type = "nav_msgs/Path"
    default_topic = "/move_base/NavfnROS/plan"
    props = (
        Prop("Color", (25, 255, 0), "color"),
        Prop("Alpha", 1.0, "float"),
        Prop("Line Style", "Lines", "choice", ("Lines", "Billboards")),
        Prop("Line Width", 0.03, "float", low=0.001, high=1.0),
        Prop("Buffer Length", 1, "int", low=1, high=100, step=1),
    )

    def line(self) -> dict[str, Any]:
        return line_style(self.values)

    def draw(self, msg: Any, pose: Transform) -> None:
        if len(msg.poses) < 2:
            self.forget("lines")
            return
        pts = np.array(
            [[p.pose.position.x, p.pose.position.y, p.pose.position.z] for p in msg.poses]
        )
        pts = transform_points(pose, pts)
        self.show_segments(np.stack([pts[:-1], pts[1:]], axis=1).astype(np.float32))


class PoseDisplay(_Segments):
    cls = "rviz/Pose"
    type_name = "Pose"
    msg_type = "geometry_msgs/PoseStamped"
    default_topic = "/move_base_simple/goal"
    props = _ARROW

    def draw(self, msg: Any, pose: Transform) -> None:
        self.show_segments(
            arrow_segments(pose @ msg_pose(msg.pose), float(self.values["Shaft Length"]))
        )


class PoseArrayDisplay(_Segments):
    cls = "rviz/PoseArray"
    type_name = "PoseArray"
    msg_type = "geometry_msgs/PoseArray"
    default_topic = "/particlecloud"
    props = (
        Prop("Color", (255, 25, 0), "color"),
        Prop("Alpha", 1.0, "float"),
        Prop("Shape", "Arrow (Flat)", "choice", ("Arrow (Flat)", "Arrow (3D)", "Axes")),
        Prop("Arrow Length", 0.3, "float", low=0.01, high=5.0),
    )

    def line(self) -> dict[str, Any]:
        # rviz draws flat arrows (amcl's thousands of particles) as pixel-wide lines
        return line_style({}) if self.values["Shape"] == "Arrow (Flat)" else super().line()

    def draw(self, msg: Any, pose: Transform) -> None:
        length = float(self.values["Arrow Length"])
        segments = [arrow_segments(pose @ msg_pose(p), length) for p in msg.poses]
        self.show_segments(
            np.concatenate(segments) if segments else np.zeros((0, 2, 3), np.float32)
        )


class PolygonDisplay(_Segments):
    cls = "rviz/Polygon"
    type_name = "Polygon"
    msg_type = "geometry_msgs/PolygonStamped"
    default_topic = "/move_base/local_costmap/footprint"
    props = (Prop("Color", (25, 255, 0), "color"), Prop("Alpha", 1.0, "float"))

    def line(self) -> dict[str, Any]:
        return line_style({})  # rviz's footprint is a line strip, a pixel wide

    def draw(self, msg: Any, pose: Transform) -> None:
        points = msg.polygon.points
        if len(points) < 2:
            self.forget("lines")
            return
        pts = transform_points(pose, np.array([[p.x, p.y, p.z] for p in points], dtype=np.float64))
        closed = np.concatenate([pts, pts[:1]])
        self.show_segments(np.stack([closed[:-1], closed[1:]], axis=1).astype(np.float32))


class PointStampedDisplay(Display):
    cls = "rviz/PointStamped"
    type_name = "PointStamped"
    msg_type = "geometry_msgs/PointStamped"
    default_topic = "/clicked_point"
    props = (
        Prop("Color", (204, 41, 204), "color"),
        Prop("Alpha", 1.0, "float"),
        Prop("Radius", 0.2, "float", low=0.01, high=5.0),
        Prop("History Length", 1, "int", low=1, high=1000, step=1),
    )

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.history: deque[tuple[float, float, float]] = deque()
        super().__init__(*args, **kwargs)

    def draw(self, msg: Any, pose: Transform) -> None:
        p = msg.point
        self.history.append(tuple(transform_points(pose, np.array([[p.x, p.y, p.z]]))[0]))
        while len(self.history) > max(1, int(self.values["History Length"])):
            self.history.popleft()
        handle = self.ctx.scene.add_point_cloud(
            f"{self.base}/points",
            np.array(self.history, dtype=np.float32),
            tuple(self.values["Color"]),
            point_size=float(self.values["Radius"]),  # viser: about 2 s wide
            point_shape="circle",
            precision="float32",
        )
        self.keep("points", handle)


class MarkerDisplay(Display):
    """visualization_msgs/Marker by namespace and id; DELETE and DELETEALL as rviz."""

    cls = "rviz/Marker"
    type_name = "Marker"
    msg_type = "visualization_msgs/Marker"
    default_topic = "/visualization_marker"

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.expiry: dict[str, int] = {}
        """Markers with a lifetime: when (graph time, ns) they go, as rviz drops them."""
        self.locked: dict[str, tuple[str, Transform]] = {}
        """frame_locked markers: their frame and pose in it, moved with the frame each frame."""
        super().__init__(*args, **kwargs)

    def draw(self, msg: Any, pose: Transform) -> None:
        self.draw_marker(msg, pose)

    def tick(self, fixed: str) -> None:
        now = self.ctx.now_ns()
        for key, when in list(self.expiry.items()):
            if now >= when:
                self.drop(key)
        for key, (frame, in_frame) in list(self.locked.items()):
            pose = self.latest_pose(frame, fixed)
            handle = self.handles.get(key)
            if pose is not None and handle is not None:
                self.keep(key, handle, pose @ in_frame)

    def drop(self, key: str) -> None:
        self.forget(key)
        self.expiry.pop(key, None)
        self.locked.pop(key, None)

    def draw_marker(self, m: Any, pose: Transform) -> None:
        key = f"{m.ns}/{m.id}"
        if m.action == 3:  # DELETEALL
            for k in list(self.handles):
                self.drop(k)
            return
        if m.action == 2:  # DELETE
            self.drop(key)
            return
        where = pose @ msg_pose(m.pose)
        lifetime = int(m.lifetime.sec) * NS + int(m.lifetime.nanosec)
        if lifetime > 0:  # from when it came, as rviz counts it
            self.expiry[key] = self.ctx.now_ns() + lifetime
        else:
            self.expiry.pop(key, None)
        if m.frame_locked:
            self.locked[key] = (str(m.header.frame_id), msg_pose(m.pose))
        else:
            self.locked.pop(key, None)
        color = (round(m.color.r * 255), round(m.color.g * 255), round(m.color.b * 255))
        opacity = m.color.a if m.color.a < 1 else None
        name = f"{self.base}/{key}"
        s = (m.scale.x, m.scale.y, m.scale.z)
        scene = self.ctx.scene
        if m.type == 1:
            h = scene.add_box(name, color=color, dimensions=s, opacity=opacity)
        elif m.type == 2:
            h = scene.add_icosphere(name, radius=max(s) / 2, color=color, opacity=opacity)
        elif m.type == 3:
            h = scene.add_cylinder(name, radius=s[0] / 2, height=s[2], color=color, opacity=opacity)
        elif m.type in (4, 5, 6, 7, 8) and m.points:
            pts = np.array([[p.x, p.y, p.z] for p in m.points], dtype=np.float32)
            if m.type in (6, 7, 8):  # cubes, spheres, points: as points of the scale's size
                h = scene.add_point_cloud(
                    name, pts, color, point_size=max(s[0], 0.01) / 2, precision="float32"
                )  # viser draws a point of size s about 2 s wide
            else:
                segs = (
                    np.stack([pts[:-1], pts[1:]], axis=1)
                    if m.type == 4
                    else pts[: len(pts) // 2 * 2].reshape(-1, 2, 3)
                )
                h = scene.add_line_segments(name, segs, color, thickness=max(s[0], 0.005))
        elif m.type == 9:
            h = scene.add_label(name, m.text)
        elif m.type == 0:
            h = scene.add_line_segments(
                name, arrow_segments(Transform(), max(s[0], 0.1)), color, thickness=max(s[1], 0.01)
            )
        else:
            return
        self.keep(key, h, where)


class MarkerArrayDisplay(MarkerDisplay):
    cls = "rviz/MarkerArray"
    type_name = "MarkerArray"
    msg_type = "visualization_msgs/MarkerArray"
    default_topic = "/visualization_marker_array"

    def on_message(self, msg: Any) -> None:
        # Each marker has its own header: queue them one by one for the message filter.
        for marker in msg.markers:
            super().on_message(marker)
        self.received += 1 - len(msg.markers)
