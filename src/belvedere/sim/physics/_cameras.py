"""Gazebo's camera sensors with their ROS plugins: ``camera`` +
``libgazebo_ros_camera.so``, ``depth`` + ``libgazebo_ros_openni_kinect.so``.

Cameras are lazy (nothing is rendered while nobody subscribes) and render visual geometry
offscreen (EGL), shadows off. Noise is gaussian from the simulation's seed.
"""

from __future__ import annotations

import logging
import math
import time
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import XmlData, transform
from belvedere.msgs import build, types
from belvedere.sim.physics._plugin import PluginContext
from belvedere.sim.physics._sensors import _num, _Sensor
from belvedere.sim.physics._spec import CAMERA_GROUPS, ModelError

__all__ = ["IMAGE_FORMATS", "CameraSensor", "DepthCamera", "encode_pixels"]

logger = logging.getLogger("belvedere.physics")

# MuJoCo cameras look along -z with y up; Gazebo's along +x with z up.
_GAZEBO_TO_MUJOCO_CAMERA = np.array(
    [[0.0, 0.0, -1.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
)


IMAGE_FORMATS: dict[str, str] = {
    "L8": "mono8",
    "L_INT8": "mono8",
    "L16": "mono16",
    "L_INT16": "mono16",
    "R8G8B8": "rgb8",
    "RGB_INT8": "rgb8",
    "B8G8R8": "bgr8",
    "BGR_INT8": "bgr8",
    "R16G16B16": "rgb16",
    "RGB_INT16": "rgb16",
    "BAYER_RGGB8": "bayer_rggb8",
    "BAYER_BGGR8": "bayer_bggr8",
    "BAYER_GBRG8": "bayer_gbrg8",
    "BAYER_GRBG8": "bayer_grbg8",
}
"""Gazebo's camera ``<image><format>`` names → ROS image encodings (gazebo_ros_camera_utils)."""


def _image_encoding(sensor: str, camera: XmlData) -> str:
    """The ROS encoding of a camera's ``<format>``; an unknown one is a warning naming its
    line, and R8G8B8, as Gazebo falls back to."""
    image = camera.child("image")
    element = image.child("format") if image is not None else None
    if element is None or not element.text.strip():
        return "rgb8"
    name = element.text.strip()
    encoding = IMAGE_FORMATS.get(name)
    if encoding is None:
        where = element.source.best or camera.source.best or "<camera>"
        logger.warning(
            "%s: warning: camera sensor %r: unknown image format %r (Gazebo's: %s); using "
            "R8G8B8, as Gazebo does",
            where,
            sensor,
            name,
            ", ".join(IMAGE_FORMATS),
        )
        return "rgb8"
    return encoding


_BAYER_OFFSETS = {
    "rggb": (0, 1, 1, 2),
    "bggr": (2, 1, 1, 0),
    "gbrg": (1, 2, 0, 1),
    "grbg": (1, 0, 2, 1),
}
"""Per Bayer pattern: the channel at (even row, even col), (even, odd), (odd, even), (odd, odd)."""


def encode_pixels(rgb: npt.NDArray[np.uint8], encoding: str) -> npt.NDArray[Any]:
    """A (height, width, 3) RGB render in a ROS image encoding (rgb8: ``rgb`` itself)."""
    if encoding == "rgb8":
        return rgb
    if encoding == "bgr8":
        return np.ascontiguousarray(rgb[:, :, ::-1])
    if encoding in ("mono8", "mono16"):
        grey: npt.NDArray[np.float64] = rgb.mean(axis=2)
        if encoding == "mono8":
            return grey.astype(np.uint8)
        return (grey * 257).astype("<u2")
    if encoding == "rgb16":
        wide: npt.NDArray[np.uint16] = rgb.astype("<u2") * np.uint16(257)
        return wide
    channels = _BAYER_OFFSETS[encoding.removeprefix("bayer_").removesuffix("8")]
    out = np.empty(rgb.shape[:2], dtype=np.uint8)
    for (row, col), channel in zip(((0, 0), (0, 1), (1, 0), (1, 1)), channels, strict=True):
        out[row::2, col::2] = rgb[row::2, col::2, channel]
    return out


class _Renderer:
    """An offscreen MuJoCo renderer for one camera at its own resolution (made on first use,
    remade after a recompile). It keeps its GL context, scene and pixel buffers from frame
    to frame, renders without multisampling, reflections or fog (shadows only where the
    world asks for them), and times what it does. Rendering that is impossible here is one
    error, then silence."""

    def __init__(self, width: int, height: int) -> None:
        self.width = width
        self.height = height
        self.model: Any = None
        self.failed = False
        self.frames = 0
        """Frames rendered (a camera nobody listens to renders none)."""
        self.seconds = 0.0
        """Wall-clock time spent rendering and reading pixels back."""
        self._gl: Any = None
        self._context: Any = None
        self._scene: Any = None
        self._camera = mujoco.MjvCamera()
        self._camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
        self._option = mujoco.MjvOption()
        self._option.geomgroup[:] = 0
        for group in CAMERA_GROUPS:
            self._option.geomgroup[group] = 1
        self._rect = mujoco.MjrRect(0, 0, width, height)
        self._rgb = np.empty((height, width, 3), dtype=np.uint8)
        self._depth = np.empty((height, width), dtype=np.float32)

    def _setup(self, engine: Any) -> None:
        self.close()
        model = engine.m
        self._gl = mujoco.GLContext(self.width, self.height)
        self._gl.make_current()
        self._context = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_100)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._context)
        self._context.readDepthMap = mujoco.mjtDepthMap.mjDEPTH_ZEROFAR
        self._scene = mujoco.MjvScene(model, maxgeom=max(1000, 2 * model.ngeom))
        flags = self._scene.flags
        flags[mujoco.mjtRndFlag.mjRND_SHADOW] = bool(np.any(model.light_castshadow))
        for flag in ("mjRND_REFLECTION", "mjRND_FOG", "mjRND_HAZE", "mjRND_WIREFRAME"):
            flags[getattr(mujoco.mjtRndFlag, flag)] = 0
        flags[mujoco.mjtRndFlag.mjRND_SKYBOX] = 1
        self.model = model

    def render(self, engine: Any, camera: str, *, depth: bool) -> npt.NDArray[Any] | None:
        """The camera's image, top row first: a new (height, width, 3) uint8 array, or for
        ``depth`` a new (height, width) float32 array of distances along the view axis (0
        where nothing is)."""
        if self.failed:
            return None
        try:
            start = time.perf_counter()
            if self._context is None or self.model is not engine.m:
                self._setup(engine)
            self._gl.make_current()
            self._camera.fixedcamid = mujoco.mj_name2id(
                engine.m, mujoco.mjtObj.mjOBJ_CAMERA, camera
            )
            mujoco.mjv_updateScene(
                engine.m,
                engine.d,
                self._option,
                None,
                self._camera,
                mujoco.mjtCatBit.mjCAT_ALL,
                self._scene,
            )
            mujoco.mjr_render(self._rect, self._scene, self._context)
            if depth:
                mujoco.mjr_readPixels(None, self._depth, self._rect, self._context)
                image: npt.NDArray[Any] = self._linear_depth(engine.m)
            else:
                mujoco.mjr_readPixels(self._rgb, None, self._rect, self._context)
                image = np.empty_like(self._rgb)
                np.copyto(image, self._rgb[::-1])  # OpenGL's rows run bottom-up
            self.frames += 1
            self.seconds += time.perf_counter() - start
            return image
        except Exception as err:  # noqa: BLE001 (say it once, keep simulating)
            self.failed = True
            hint = ""
            if "gl" in str(err).lower() or "egl" in str(err).lower():
                hint = "; install Mesa's EGL (libegl1 libgl1-mesa-dri) or set MUJOCO_GL=osmesa"
            logger.error("camera rendering failed: %s%s", str(err).splitlines()[0], hint)
            return None

    def _linear_depth(self, model: Any) -> npt.NDArray[np.float32]:
        """OpenGL's depth buffer (0 near … 1 far) as metres, as MuJoCo's Renderer does."""
        extent = model.stat.extent
        near = np.float32(model.vis.map.znear * extent)
        far = np.float32(model.vis.map.zfar * extent)
        c = np.float32(-0.5) * (-(far + near) / (far - near)) - np.float32(0.5)
        d = np.float32(-0.5) * (-(np.float32(2) * far * near) / (far - near))
        out: npt.NDArray[np.float32] = (d / (self._depth[::-1] + c)).astype(np.float32)
        return out

    def close(self) -> None:
        if self._context is not None:
            self._gl.make_current()
            self._context.free()
            self._context = None
        if self._gl is not None:
            self._gl.free()
            self._gl = None
        self.model = None


class CameraSensor(_Sensor):
    """``libgazebo_ros_camera.so``: Image and CameraInfo on ``<cameraName>/…``."""

    IMAGE_DEFAULT = "image_raw"
    INFO_DEFAULT = "camera_info"

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        assert ctx.sensor is not None  # registered as a sensor plugin only
        self.sensor = ctx.sensor
        camera = self.sensor.child("camera")
        if camera is None:
            msg = f"camera sensor {self.sensor_name!r} needs <camera>"
            raise ModelError(msg, self.sensor.source.best)
        self.width = int(_num(camera, 320, "image", "width"))
        self.height = int(_num(camera, 240, "image", "height"))
        self.hfov = _num(camera, 1.047, "horizontal_fov")
        self.near = _num(camera, 0.1, "clip", "near")
        self.far = _num(camera, 100.0, "clip", "far")
        self.encoding = _image_encoding(self.sensor_name, camera)
        self.focal = self.number("focalLength", 0.0) or self.width / (2 * math.tan(self.hfov / 2))
        self.cx = self.number("Cx", 0.0) or (self.width + 1) / 2
        self.cy = self.number("Cy", 0.0) or (self.height + 1) / 2
        self.baseline = self.number("hackBaseline", 0.0)
        name = self.text("cameraName", "") or ""
        self.prefix = name.strip("/") + "/" if name.strip("/") else ""
        self.node = self.make_node()
        # Queue size 1: the newest frame, never a backlog (see the graph's transport).
        self.image_pub = self.node.publisher(
            self.prefix + (self.text("imageTopicName") or self.IMAGE_DEFAULT),
            "sensor_msgs/Image",
            queue_size=1,
        )
        self.info_pub = self.node.publisher(
            self.prefix + (self.text("cameraInfoTopicName") or self.INFO_DEFAULT),
            "sensor_msgs/CameraInfo",
            queue_size=2,
        )
        self.camera_name = f"{self.robot.name}/{self.ctx.name}/camera"
        self.renderer = _Renderer(self.width, self.height)
        self.image_type = types().cls("sensor_msgs/Image")
        self.encode_seconds = 0.0
        """Wall-clock time spent making Image messages of rendered frames."""

    def prepare(self, spec: mujoco.MjSpec) -> None:
        offscreen = spec.visual.global_
        offscreen.offwidth = max(offscreen.offwidth, self.width)
        offscreen.offheight = max(offscreen.offheight, self.height)
        # No multisampling: on a CPU it costs 4x the rendering and reading back.
        spec.visual.quality.offsamples = 0
        body, offset = self.robot.link_body[self.link]
        parent = spec.worldbody if body == "world" else spec.body(body)
        frame = offset @ transform(self.pose) @ _GAZEBO_TO_MUJOCO_CAMERA
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, np.ascontiguousarray(frame[:3, :3]).reshape(9))
        fovy = 2 * math.degrees(math.atan(math.tan(self.hfov / 2) * self.height / self.width))
        camera = parent.add_camera(name=self.camera_name, fovy=fovy)
        camera.pos = [float(v) for v in frame[:3, 3]]
        camera.quat = [float(v) for v in quat]

    def wanted(self) -> bool:
        return self.image_pub.wanted or self.info_pub.wanted

    def update(self, now_ns: int) -> None:
        if not self.wanted() or not self.due(now_ns):
            return
        if self.image_pub.wanted:
            rgb = self.renderer.render(self.engine, self.camera_name, depth=False)
            if rgb is not None:
                start = time.perf_counter()
                image = self.image(now_ns, rgb)
                self.encode_seconds += time.perf_counter() - start
                self.image_pub.publish(image)
        if self.info_pub.wanted:
            self.info_pub.publish(self.info(now_ns))

    def image(self, now_ns: int, rgb: npt.NDArray[Any]) -> Any:
        """An Image in the camera's encoding from a fresh (height, width, 3) render, whose
        pixels it takes over (rgb8: no copy)."""
        pixels = encode_pixels(rgb, self.encoding)
        return self.image_type(
            build.header(now_ns, self.frame),
            self.height,
            self.width,
            self.encoding,
            0,
            pixels.nbytes // self.height,
            pixels.reshape(-1).view(np.uint8),
        )

    def info(self, now_ns: int) -> Any:
        f, cx, cy = self.focal, self.cx, self.cy
        return types().cls("sensor_msgs/CameraInfo")(
            build.header(now_ns, self.frame),
            self.height,
            self.width,
            "plumb_bob",
            np.zeros(5),
            np.array([f, 0.0, cx, 0.0, f, cy, 0.0, 0.0, 1.0]),
            np.eye(3).reshape(-1),
            np.array([f, 0.0, cx, -f * self.baseline, 0.0, f, cy, 0.0, 0.0, 0.0, 1.0, 0.0]),
            0,
            0,
            types().cls("sensor_msgs/RegionOfInterest")(0, 0, 0, 0, False),
        )


class DepthCamera(CameraSensor):
    """``libgazebo_ros_openni_kinect.so``: RGB, depth (32FC1 m, or 16UC1 mm) and points."""

    IMAGE_DEFAULT = "rgb/image_raw"
    INFO_DEFAULT = "rgb/camera_info"

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        self.depth_pub = self.node.publisher(
            self.prefix + (self.text("depthImageTopicName") or "depth/image_raw"),
            "sensor_msgs/Image",
            queue_size=2,
        )
        self.depth_info_pub = self.node.publisher(
            self.prefix + (self.text("depthImageCameraInfoTopicName") or "depth/camera_info"),
            "sensor_msgs/CameraInfo",
            queue_size=2,
        )
        self.points_pub = self.node.publisher(
            self.prefix + (self.text("pointCloudTopicName") or "depth/points"),
            "sensor_msgs/PointCloud2",
            queue_size=2,
        )
        self.cutoff = self.number("pointCloudCutoff", 0.4)
        self.cutoff_max = self.number("pointCloudCutoffMax", 5.0)
        self.depth16 = self.flag("useDepth16UC1Format", False)
        self.depth_renderer = _Renderer(self.width, self.height)

    def wanted(self) -> bool:
        return super().wanted() or any(
            p.wanted for p in (self.depth_pub, self.depth_info_pub, self.points_pub)
        )

    def update(self, now_ns: int) -> None:
        if not self.wanted() or not self.due(now_ns):
            return
        rgb = None
        if self.image_pub.wanted or self.points_pub.wanted:
            rgb = self.renderer.render(self.engine, self.camera_name, depth=False)
        if rgb is not None and self.image_pub.wanted:
            self.image_pub.publish(self.image(now_ns, rgb))
        if self.info_pub.wanted:
            self.info_pub.publish(self.info(now_ns))
        if self.depth_info_pub.wanted:
            self.depth_info_pub.publish(self.info(now_ns))
        if self.depth_pub.wanted or self.points_pub.wanted:
            depth = self.depth_renderer.render(self.engine, self.camera_name, depth=True)
            if depth is None:
                return
            depth = depth.astype(np.float32)
            depth[(depth >= self.far) | (depth <= 0)] = np.nan
            if self.depth_pub.wanted:
                self.depth_pub.publish(self.depth_image(now_ns, depth))
            if self.points_pub.wanted and rgb is not None:
                self.points_pub.publish(self.points(now_ns, depth, rgb))

    def depth_image(self, now_ns: int, depth: npt.NDArray[np.float32]) -> Any:
        if self.depth16:
            mm = np.nan_to_num(depth * 1000.0, nan=0.0).astype(np.uint16)
            data, encoding, step = mm.view(np.uint8).reshape(-1), "16UC1", self.width * 2
        else:
            data, encoding, step = depth.view(np.uint8).reshape(-1), "32FC1", self.width * 4
        return types().cls("sensor_msgs/Image")(
            build.header(now_ns, self.frame), self.height, self.width, encoding, 0, step, data
        )

    def points(self, now_ns: int, depth: npt.NDArray[np.float32], rgb: npt.NDArray[Any]) -> Any:
        v, u = np.mgrid[0 : self.height, 0 : self.width].astype(np.float32)
        z = depth.copy()
        z[(z < self.cutoff) | (z > self.cutoff_max)] = np.nan
        x = (u - (self.cx - 1)) * z / self.focal
        y = (v - (self.cy - 1)) * z / self.focal
        packed = (
            (rgb[:, :, 0].astype(np.uint32) << 16)
            | (rgb[:, :, 1].astype(np.uint32) << 8)
            | rgb[:, :, 2].astype(np.uint32)
        )
        cloud = np.zeros(
            (self.height, self.width),
            dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgb", "<u4")],
        )
        cloud["x"], cloud["y"], cloud["z"], cloud["rgb"] = x, y, z, packed
        field = types().cls("sensor_msgs/PointField")
        fields = [field(n, o, 7, 1) for n, o in (("x", 0), ("y", 4), ("z", 8))]
        fields.append(field("rgb", 12, 7, 1))
        return types().cls("sensor_msgs/PointCloud2")(
            build.header(now_ns, self.frame),
            self.height,
            self.width,
            fields,
            False,
            16,
            16 * self.width,
            cloud.view(np.uint8).reshape(-1),
            False,
        )
