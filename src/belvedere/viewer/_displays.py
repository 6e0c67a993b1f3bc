"""Displays of sensor data and maps: LaserScan, PointCloud2, Map, Image and Camera."""

from __future__ import annotations

import math
from collections import deque
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.graph import NS
from belvedere.msgs import ImageError, image_rgb
from belvedere.tf import Transform
from belvedere.viewer._display import Display, Prop, transform_points
from belvedere.viewer._page import sharpen_texels
from belvedere.viewer._status import Level

__all__ = [
    "CameraDisplay",
    "ImageDisplay",
    "LaserScanDisplay",
    "MapDisplay",
    "PointCloud2Display",
    "msg_pose",
    "rainbow",
]

F64 = npt.NDArray[np.float64]
U8 = npt.NDArray[np.uint8]


def msg_pose(p: Any) -> Transform:
    """A geometry_msgs/Pose (an all-zero quaternion, the message default, is identity)."""
    q = p.orientation
    xyzw = (q.x, q.y, q.z, q.w) if (q.x, q.y, q.z, q.w) != (0, 0, 0, 0) else (0.0, 0.0, 0.0, 1.0)
    return Transform((p.position.x, p.position.y, p.position.z), xyzw)


def rainbow(values: F64) -> U8:
    """rviz's rainbow ramp: 0 magenta → blue → cyan → green → yellow → 1 red."""
    v = np.clip(values, 0.0, 1.0)
    h = v * 5.0 + 1.0
    i = np.floor(h)
    f = h - i
    f = np.where(i % 2 == 0, 1.0 - f, f)
    n = 1.0 - f
    one, zero = np.ones_like(v), np.zeros_like(v)
    conditions = [i <= 1, i == 2, i == 3, i == 4]
    r = np.select(conditions, [n, zero, zero, n], one)
    g = np.select(conditions, [zero, n, one, one], n)
    b = np.select(conditions, [one, one, n, zero], zero)
    out: U8 = (np.stack([r, g, b], axis=1) * 255).round().astype(np.uint8)
    return out


POINT_STYLES = ("Points", "Squares", "Flat Squares", "Spheres", "Boxes")
COLOR_TRANSFORMERS = ("Intensity", "FlatColor", "AxisColor", "RGB8")


class _CloudDisplay(Display):
    """Points kept in the fixed frame for Decay Time seconds (0: the latest message only)."""

    props = (
        Prop("Style", "Flat Squares", "choice", POINT_STYLES),
        Prop("Size (m)", 0.01, "float", low=0.001, high=0.5, step=0.001),
        Prop("Size (Pixels)", 3, "int", low=1, high=20, step=1),
        Prop("Alpha", 1.0, "float"),
        Prop("Decay Time", 0.0, "float", low=0.0, high=60.0, step=0.1),
        Prop("Color Transformer", "Intensity", "choice", COLOR_TRANSFORMERS),
        Prop("Color", (255, 255, 255), "color"),
        Prop("Use rainbow", True, "bool"),
        Prop("Invert Rainbow", False, "bool"),
        Prop("Min Color", (0, 0, 0), "color"),
        Prop("Max Color", (255, 255, 255), "color"),
        Prop("Axis", "Z", "choice", ("X", "Y", "Z")),
    )

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.clouds: deque[tuple[int, F64, U8]] = deque()
        self.changed_since_drawn = False
        self.painted: tuple[int, ...] | None = None
        """The one colour the drawn cloud has (None: a colour per point)."""
        super().__init__(*args, **kwargs)

    def points(self, msg: Any) -> tuple[F64, F64 | None, U8 | None]:
        """(N, 3) points in the message's frame, their intensities, their own colours."""
        raise NotImplementedError

    def colors(self, pts: F64, intensity: F64 | None, own: U8 | None) -> U8:
        transformer = self.values["Color Transformer"]
        n = len(pts)
        if transformer == "RGB8" and own is not None:
            return own
        if (
            transformer == "FlatColor"
            or (transformer == "Intensity" and intensity is None)
            or (transformer == "RGB8" and own is None)
        ):
            return np.tile(np.array(self.values["Color"], dtype=np.uint8), (n, 1))
        if transformer == "AxisColor":
            values = pts[:, "XYZ".index(self.values["Axis"])]
        else:
            assert intensity is not None
            values = intensity
        lo, hi = (float(values.min()), float(values.max())) if n else (0.0, 0.0)
        # rviz: equal values all take the top of the ramp
        t = (values - lo) / (hi - lo) if hi > lo else np.ones(n)
        if self.values["Use rainbow"] or transformer == "AxisColor":
            return rainbow(1.0 - t if self.values["Invert Rainbow"] else t)
        low = np.array(self.values["Min Color"], dtype=np.float64)
        high = np.array(self.values["Max Color"], dtype=np.float64)
        mixed: U8 = (low + (high - low) * t[:, None]).round().astype(np.uint8)
        return mixed

    def draw(self, msg: Any, pose: Transform) -> None:
        pts, intensity, own = self.points(msg)
        stamp = int(msg.header.stamp.sec) * NS + int(msg.header.stamp.nanosec)
        colors = self.colors(pts, intensity, own)
        self.clouds.append((stamp, transform_points(pose, pts), colors))
        self.changed_since_drawn = True

    def tick(self, fixed: str) -> None:
        decay = float(self.values["Decay Time"])
        if decay <= 0:
            while len(self.clouds) > 1:
                self.clouds.popleft()
                self.changed_since_drawn = True
        else:
            horizon = self.ctx.now_ns() - round(decay * NS)
            while len(self.clouds) > 1 and self.clouds[0][0] < horizon:
                self.clouds.popleft()
                self.changed_since_drawn = True
        if not self.changed_since_drawn or not self.clouds:
            return
        self.changed_since_drawn = False
        pts = np.concatenate([c[1] for c in self.clouds])
        colors = np.concatenate([c[2] for c in self.clouds])
        if len(pts) == 0:
            pts, colors = np.zeros((1, 3)), np.zeros((1, 3), dtype=np.uint8)
        style = self.values["Style"]
        # viser draws a point of size s about 2 s wide on screen (its scale lacks the frustum's
        # factor 2): half of rviz's width gives rviz's squares.
        size = (
            float(self.values["Size (Pixels)"]) * 0.005
            if style == "Points"
            else float(self.values["Size (m)"])
        ) / 2
        # One colour for all (FlatColor) is the material's, not a colour per point: the
        # browser then keeps its material while the points change.
        flat = bool((colors == colors[0]).all())
        paint: Any = tuple(int(c) for c in colors[0]) if flat else colors
        handle = self.handles.get("points")
        if handle is not None and (
            (flat and paint == self.painted)
            or (not flat and self.painted is None and len(pts) == len(handle.points))
        ):  # new points into the same node (points and colours always of one length)
            if not flat:
                handle.colors = colors
            handle.points = pts.astype(np.float32)
            self.keep("points", handle)
            return
        self.painted = paint if flat else None
        handle = self.ctx.scene.add_point_cloud(
            f"{self.base}/points",
            pts.astype(np.float32),
            paint,
            point_size=size,
            point_shape="circle" if style in ("Points", "Spheres") else "square",
            point_shading="gradient" if style == "Spheres" else "flat",
            precision="float32",
        )
        self.keep("points", handle)

    def changed(self, key: str) -> None:
        if key in ("Style", "Size (m)", "Size (Pixels)"):
            self.forget("points")
            self.changed_since_drawn = True

    def reset(self) -> None:
        self.clouds.clear()
        super().reset()


class LaserScanDisplay(_CloudDisplay):
    cls = "rviz/LaserScan"
    type_name = "LaserScan"
    msg_type = "sensor_msgs/LaserScan"
    default_topic = "/scan"

    def points(self, msg: Any) -> tuple[F64, F64 | None, U8 | None]:
        ranges = np.asarray(msg.ranges, dtype=np.float64)
        angles = msg.angle_min + np.arange(len(ranges)) * msg.angle_increment
        ok = np.isfinite(ranges) & (ranges >= msg.range_min) & (ranges <= msg.range_max)
        r, a = ranges[ok], angles[ok]
        pts = np.stack([r * np.cos(a), r * np.sin(a), np.zeros_like(r)], axis=1)
        intensities = np.asarray(msg.intensities, dtype=np.float64)
        intensity = intensities[ok] if len(intensities) == len(ranges) else np.zeros(len(r))
        return pts, intensity, None


class PointCloud2Display(_CloudDisplay):
    cls = "rviz/PointCloud2"
    type_name = "PointCloud2"
    msg_type = "sensor_msgs/PointCloud2"
    default_topic = "/points"

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        given = kwargs.get("values") or {}
        self.transformer_given = bool(given.get("Color Transformer"))
        """A config (or the user) chose the colour transformer: the cloud's fields do not
        (rviz saves an unchosen one as "")."""
        super().__init__(*args, **kwargs)

    def set_value(self, key: str, value: Any) -> None:
        if key == "Color Transformer" and hasattr(self, "handles"):
            self.transformer_given = True  # the user's choice, after the display was made
        super().set_value(key, value)

    def points(self, msg: Any) -> tuple[F64, F64 | None, U8 | None]:
        offsets = {f.name: f.offset for f in msg.fields}
        colour = next((name for name in ("rgb", "rgba") if name in offsets), None)
        if not self.transformer_given:
            # rviz picks a new display's transformer from the first cloud's fields: a
            # Kinect's x, y, z, rgb shows its colours, not a flat Intensity without intensity
            self.transformer_given = True
            self.values["Color Transformer"] = "RGB8" if colour is not None else "Intensity"
        if not {"x", "y", "z"} <= set(offsets):
            self.status.set("Points", Level.ERROR, "the cloud has no x, y, z fields")
            return np.zeros((0, 3)), None, None
        self.status.clear("Points")
        data = np.frombuffer(bytes(msg.data), dtype=np.uint8).reshape(-1, msg.point_step)
        order = ">" if msg.is_bigendian else "<"

        def column(name: str) -> F64:
            at = offsets[name]
            return data[:, at : at + 4].copy().view(f"{order}f4")[:, 0].astype(np.float64)

        pts = np.stack([column(a) for a in "xyz"], axis=1)
        ok = np.isfinite(pts).all(axis=1)
        intensity = column("intensity")[ok] if "intensity" in offsets else None
        own = None
        if colour is not None:
            at = offsets[colour]
            raw = data[ok, at : at + 4]
            # packed as float bytes b, g, r, (pad) in little-endian order
            own = np.ascontiguousarray(raw[:, [2, 1, 0]] if order == "<" else raw[:, [1, 2, 3]])
        return pts[ok], intensity, own


def _palette(scheme: str) -> U8:
    """RGBA for each cell byte 0..255 (-1 is 255) in rviz's map, costmap and raw schemes."""
    table = np.zeros((256, 4), dtype=np.uint8)
    v = np.arange(256)
    if scheme == "costmap":
        ramp = v[1:99]
        table[1:99, 0] = ramp * 255 // 100
        table[1:99, 2] = 255 - ramp * 255 // 100
        table[1:99, 3] = 255
        table[99] = (0, 255, 255, 255)  # inscribed
        table[100] = (255, 0, 255, 255)  # lethal
        table[101:255] = (0, 255, 0, 255)  # not a cost
        table[255] = (112, 137, 134, 255)  # unknown
    elif scheme == "raw":
        table[:, :3] = v[:, None]
        table[:, 3] = 255
    else:
        gray = 255 - v[:101] * 255 // 100
        table[:101, :3] = gray[:, None]
        table[:, 3] = 255
        table[101:128] = (0, 255, 0, 255)
        t = (v[128:255] - 128) / 126
        table[128:255, 0] = 255
        table[128:255, 1] = (t * 255).astype(np.uint8)
        table[255] = (112, 137, 134, 255)  # unknown: rviz's grey-green
    return table


class MapDisplay(Display):
    """An OccupancyGrid as one textured plane, redrawn when a new grid comes (a SLAM map grows),
    moved with its frame's latest transform in between (as rviz does)."""

    cls = "rviz/Map"
    type_name = "Map"
    msg_type = "nav_msgs/OccupancyGrid"
    default_topic = "/map"
    stamped = False
    props = (
        Prop("Alpha", 0.7, "float"),
        Prop("Color Scheme", "map", "choice", ("map", "costmap", "raw")),
        Prop("Draw Behind", False, "bool"),
    )
    drawn: Any = None
    """The message the scene shows."""
    image: U8 | None = None
    """(height, width, 4) RGBA of its cells, row 0 at the map's origin."""
    sharpened = False
    """Whether the pages were told to draw its texture texel by texel."""

    def update(self, msg: Any, fixed: str) -> None:
        if msg is None:
            return
        info = msg.info
        if info.width == 0 or info.height == 0:
            self.status.set("Map", Level.WARN, "Map is zero-sized")
            return
        pose = self.latest_pose(msg.header.frame_id, fixed)
        if pose is None:
            return
        origin = msg_pose(info.origin)
        w, h = info.width * info.resolution, info.height * info.resolution
        # Just under the plane z = 0, where the Grid display's (depth-writing) lines lie: at the
        # same height the two fight over each pixel, and a software renderer's depth still
        # cannot tell them apart 2 mm apart a few metres away.
        below = -0.02 if self.values["Draw Behind"] else -0.01
        center = origin @ Transform((w / 2, h / 2, below))
        if msg is not self.drawn or "grid" not in self.handles:
            cells = np.asarray(msg.data, dtype=np.int16).reshape(info.height, info.width)
            rgba = _palette(self.values["Color Scheme"])[cells.astype(np.uint8)]
            rgba[..., 3] = (rgba[..., 3] * float(self.values["Alpha"])).astype(np.uint8)
            self.image = rgba
            name = f"{self.base}/grid"
            if not self.sharpened:
                sharpen_texels(self.ctx.gui, name)
                self.sharpened = True
            handle = self.ctx.scene.add_image(
                name,
                np.ascontiguousarray(rgba),  # viser puts row 0 at the plane's lowest y
                render_width=w,
                render_height=h,
                format="png",
                cast_shadow=False,
                receive_shadow=False,
            )
            self.keep("grid", handle)
            self.drawn = msg
            self.status.set(
                "Map", Level.OK, f"{info.width} x {info.height} cells at {info.resolution:g} m"
            )
        self.keep("grid", self.handles["grid"], pose @ center)

    def changed(self, key: str) -> None:
        self.drawn = None  # redraw with the new colours


IMAGE_PANEL_WIDTH = 360
"""Pixels: a 640 x 480 camera shown half size beside the 3D view, as rviz's docked Image
panel first opens (the user drags its edge to resize it)."""


class ImageDisplay(Display):
    """An image in a panel of its own docked beside the 3D view (rviz's Image panel): the
    user can resize it, move it or float it over the view."""

    cls = "rviz/Image"
    type_name = "Image"
    msg_type = "sensor_msgs/Image"
    default_topic = "/camera/image_raw"
    stamped = False
    drawn: Any = None
    picture: Any = None
    """The panel's image (it goes with the panel)."""

    def update(self, msg: Any, fixed: str) -> None:
        if msg is None or msg is self.drawn:
            return
        self.drawn = msg
        try:
            image = image_rgb(msg)
        except ImageError as err:
            self.status.set("Image", Level.ERROR, err.message)
            return
        self.status.set("Image", Level.OK, f"{msg.width} x {msg.height} {msg.encoding}")
        self.show_image(image)
        self.overlay(msg, image, fixed)

    def show_image(self, image: U8) -> None:
        if "panel" not in self.handles:
            gui = self.ctx.gui
            panel = gui.add_panel()
            with panel.add_tab(self.name):
                self.picture = gui.add_image(image, label=None)
            # one column of pictures beside the view, as rviz stacks its docked panels
            if self.ctx.docked:
                panel.dock_below(self.ctx.docked[-1])
            else:
                panel.dock_right()
                panel.set_width(IMAGE_PANEL_WIDTH)
            self.ctx.docked.append(panel)
            self.keep("panel", panel)
        else:
            self.picture.image = image

    def overlay(self, msg: Any, image: U8, fixed: str) -> None:
        """What the display draws in the 3D view besides its panel (an Image: nothing)."""

    def forget(self, key: str) -> None:
        if key == "panel" and "panel" in self.handles:
            self.ctx.docked.remove(self.handles["panel"])
            self.picture = None
        super().forget(key)


class CameraDisplay(ImageDisplay):
    """An Image display whose picture also stands in the 3D view, on the camera's frustum
    where the camera is (rviz's overlay of the image on the scene it sees)."""

    cls = "rviz/Camera"
    type_name = "Camera"
    props = (
        Prop("Overlay Alpha", 0.5, "float"),
        Prop("Zoom Factor", 1.0, "float", low=0.1, high=10.0),
    )
    FOV = math.radians(60.0)
    """The frustum's vertical angle: the Gazebo camera plugin's default (rviz reads the
    camera_info; this display has the image only)."""

    def overlay(self, msg: Any, image: U8, fixed: str) -> None:
        pose = self.latest_pose(str(msg.header.frame_id), fixed)
        if pose is None:
            return
        handle = self.handles.get("frustum")
        if handle is None:
            handle = self.ctx.scene.add_camera_frustum(
                f"{self.base}/frustum",
                fov=self.FOV,
                aspect=msg.width / max(1, msg.height),
                scale=0.3 * float(self.values["Zoom Factor"]),
                image=image,
                color=(255, 255, 255),
                cast_shadow=False,
                receive_shadow=False,
            )
        else:
            handle.image = image
        self.keep("frustum", handle, pose)
