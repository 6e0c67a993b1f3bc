"""Gazebo's sensors with their ROS plugins: ``ray``/``gpu_ray`` + the laser plugins,
``camera`` + ``libgazebo_ros_camera.so``, ``depth`` + ``libgazebo_ros_openni_kinect.so``,
``imu`` + ``libgazebo_ros_imu_sensor.so``.

Sensors are lazy: nothing is cast or rendered while nobody subscribes. A laser scan is one
``mj_multiRay`` against collision geometry; cameras render visual geometry offscreen (EGL),
shadows off. Noise is gaussian from the simulation's seed.
"""

from __future__ import annotations

import logging
import math
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import Pose, XmlData, transform
from belvedere.msgs import build, types
from belvedere.sim.physics._builder import COLLISION_GROUP, VISUAL_GROUP, ModelError
from belvedere.sim.physics._engine import quat_xyzw
from belvedere.sim.physics._plugin import Plugin, PluginContext, RateGate

__all__ = ["CameraSensor", "DepthCamera", "ImuSensor", "LaserSensor", "sensor_pose"]

logger = logging.getLogger("belvedere.physics")

Matrix4 = npt.NDArray[np.float64]

# MuJoCo cameras look along -z with y up; Gazebo's along +x with z up.
_GAZEBO_TO_MUJOCO_CAMERA = np.array(
    [[0.0, 0.0, -1.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
)


def _text(data: XmlData | None, *path: str) -> str | None:
    node = data
    for tag in path:
        node = node.child(tag) if node is not None else None
    return node.text.strip() if node is not None else None


def _num(data: XmlData | None, default: float, *path: str) -> float:
    text = _text(data, *path)
    if text is None or text == "":
        return default
    try:
        return float(text)
    except ValueError:
        where = data.source.best if data is not None else None
        msg = f"sensor: <{'/'.join(path)}> expects a number, got {text!r}"
        raise ModelError(msg, where) from None


def sensor_pose(sensor: XmlData) -> Pose:
    text = _text(sensor, "pose")
    if not text:
        return Pose()
    v = [float(x) for x in text.split()]
    if len(v) != 6:
        msg = f"sensor <pose> expects 6 numbers, got {text!r}"
        raise ModelError(msg, sensor.source.best)
    return Pose((v[0], v[1], v[2]), (v[3], v[4], v[5]))


class _Sensor(Plugin):
    """A plugin on a ``<sensor>`` (or a model plugin measuring its ``<bodyName>``): its
    frame, update rate and laziness."""

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        if ctx.sensor is None:
            self.sensor_name = ctx.name
            link = self.text("bodyName")
            if link is None or link not in self.robot.link_body:
                msg = f"plugin {ctx.name!r}: <bodyName> {link!r} is not a link of the robot"
                raise ModelError(msg, self._where("bodyName"))
            self.pose = Pose()
            rate = 0.0
        else:
            self.sensor_name = ctx.sensor.attr("name") or ctx.name
            link = ctx.reference
            if link is None or link not in self.robot.link_body:
                msg = f"sensor {self.sensor_name!r} must be inside <gazebo reference='LINK'>"
                raise ModelError(msg, ctx.sensor.source.best)
            self.pose = sensor_pose(ctx.sensor)
            rate = _num(ctx.sensor, 0.0, "update_rate")
        self.link = link
        for tag in ("updateRate", "updateRateHZ"):  # the plugin's own rate wins
            plugin_rate = self.number(tag, 0.0)
            rate = plugin_rate if plugin_rate > 0 else rate
        self.gate = RateGate(rate, ctx.graph.now_ns(), strict=False, immediate=True)
        self.frame = (self.text("frameName") or self.link).lstrip("/")

    def bind(self) -> None:
        body, offset = self.robot.link_body[self.link]
        self.body_id = self.engine.body_id(body)
        self.body_from_sensor: Matrix4 = offset @ transform(self.pose)

    def world_pose(self) -> Matrix4:
        result: Matrix4 = self.engine.body_pose(self.body_id) @ self.body_from_sensor
        return result

    def due(self, now_ns: int) -> bool:
        return self.gate.due(now_ns)

    def reset(self) -> None:
        self.gate.reset(self.ctx.graph.now_ns())


class LaserSensor(_Sensor):
    """``libgazebo_ros_laser.so`` / ``libgazebo_ros_gpu_laser.so``: LaserScan as Gazebo >= 7
    masks it (REP 117): beyond max +inf, below min -inf, noise then clamping otherwise."""

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        assert ctx.sensor is not None  # registered as a sensor plugin only
        self.sensor = ctx.sensor
        ray = self.sensor.child("ray")
        horizontal = ray.child("scan").child("horizontal") if ray and ray.child("scan") else None  # type: ignore[union-attr]
        if ray is None or horizontal is None:
            msg = f"ray sensor {self.sensor_name!r} needs <ray><scan><horizontal>"
            raise ModelError(msg, self.sensor.source.best)
        samples = int(_num(horizontal, 640, "samples"))
        resolution = _num(horizontal, 1.0, "resolution")
        self.count = max(1, round(samples * resolution))
        self.angle_min = _num(horizontal, 0.0, "min_angle")
        self.angle_max = _num(horizontal, 0.0, "max_angle")
        self.range_min = _num(ray, 0.0, "range", "min")
        self.range_max = _num(ray, 10.0, "range", "max")
        noise = ray.child("noise")
        self.noise_mean = _num(noise, 0.0, "mean") if noise is not None else 0.0
        self.noise_std = _num(noise, 0.0, "stddev") if noise is not None else 0.0
        step = (self.angle_max - self.angle_min) / (self.count - 1) if self.count > 1 else 0.0
        self.increment = step
        angles = self.angle_min + step * np.arange(self.count)
        self.directions = np.stack([np.cos(angles), np.sin(angles), np.zeros(self.count)], axis=1)
        topic = self.text("topicName", "/world") or "/world"
        self.node = self.make_node()
        self.pub = self.node.publisher(topic, "sensor_msgs/LaserScan", queue_size=1)
        self.group = np.zeros(6, dtype=np.uint8)
        self.group[COLLISION_GROUP] = 1
        self.geomid = np.zeros(self.count, dtype=np.int32)
        self.dist = np.zeros(self.count, dtype=np.float64)
        self.scan_type = types().cls("sensor_msgs/LaserScan")

    def update(self, now_ns: int) -> None:
        if not self.pub.wanted or not self.due(now_ns):
            return
        self.pub.publish(self.scan(now_ns))

    def ranges(self) -> npt.NDArray[np.float64]:
        """The current ranges (masked and noisy as published)."""
        pose = self.world_pose()
        vec = (self.directions @ pose[:3, :3].T).reshape(-1)
        mujoco.mj_multiRay(
            self.engine.m,
            self.engine.d,
            np.ascontiguousarray(pose[:3, 3]),
            np.ascontiguousarray(vec),
            self.group,
            1,
            self.body_id,
            self.geomid,
            self.dist,
            None,
            self.count,
            self.range_max * 1.01,
        )
        d = self.dist.copy()
        hit = self.geomid >= 0
        out = np.full(self.count, np.inf)
        if self.noise_std > 0 or self.noise_mean != 0:
            noisy = d + self.rng.normal(self.noise_mean, self.noise_std, self.count)
        else:
            noisy = d
        inside = hit & (d < self.range_max) & (d > self.range_min)
        out[inside] = np.clip(noisy[inside], self.range_min, self.range_max)
        out[hit & (d <= self.range_min)] = -np.inf
        return out

    def scan(self, now_ns: int) -> Any:
        ranges = self.ranges().astype(np.float32)
        return self.scan_type(
            build.header(now_ns, self.frame),
            self.angle_min,
            self.angle_max,
            self.increment,
            0.0,
            0.0,
            self.range_min,
            self.range_max,
            ranges,
            np.zeros(self.count, dtype=np.float32),
        )


class _Renderer:
    """An offscreen MuJoCo renderer for one camera (made on first use, remade after a
    recompile). Rendering that is impossible here is one error, then silence."""

    def __init__(self, width: int, height: int) -> None:
        self.width = width
        self.height = height
        self.renderer: Any = None
        self.model: Any = None
        self.failed = False

    def render(self, engine: Any, camera: str, *, depth: bool) -> npt.NDArray[Any] | None:
        if self.failed:
            return None
        try:
            if self.renderer is None or self.model is not engine.m:
                self.close()
                self.renderer = mujoco.Renderer(engine.m, self.height, self.width)
                self.model = engine.m
            options = mujoco.MjvOption()
            options.geomgroup[:] = 0
            options.geomgroup[VISUAL_GROUP] = 1
            if depth:
                self.renderer.enable_depth_rendering()
            else:
                self.renderer.disable_depth_rendering()
            self.renderer.update_scene(engine.d, camera=camera, scene_option=options)
            self.renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = 0
            image: npt.NDArray[Any] = self.renderer.render()
            return image
        except Exception as err:  # noqa: BLE001 (say it once, keep simulating)
            self.failed = True
            hint = ""
            if "gl" in str(err).lower() or "egl" in str(err).lower():
                hint = "; install Mesa's EGL (libegl1 libgl1-mesa-dri) or set MUJOCO_GL=osmesa"
            logger.error("camera rendering failed: %s%s", str(err).splitlines()[0], hint)
            return None

    def close(self) -> None:
        if self.renderer is not None:
            self.renderer.close()
            self.renderer = None


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
        fmt = (_text(camera, "image", "format") or "R8G8B8").upper()
        self.encoding = {"L8": "mono8", "B8G8R8": "bgr8"}.get(fmt, "rgb8")
        self.focal = self.number("focalLength", 0.0) or self.width / (2 * math.tan(self.hfov / 2))
        self.cx = self.number("Cx", 0.0) or (self.width + 1) / 2
        self.cy = self.number("Cy", 0.0) or (self.height + 1) / 2
        self.baseline = self.number("hackBaseline", 0.0)
        name = self.text("cameraName", "") or ""
        self.prefix = name.strip("/") + "/" if name.strip("/") else ""
        self.node = self.make_node()
        self.image_pub = self.node.publisher(
            self.prefix + (self.text("imageTopicName") or self.IMAGE_DEFAULT),
            "sensor_msgs/Image",
            queue_size=2,
        )
        self.info_pub = self.node.publisher(
            self.prefix + (self.text("cameraInfoTopicName") or self.INFO_DEFAULT),
            "sensor_msgs/CameraInfo",
            queue_size=2,
        )
        self.camera_name = f"{self.robot.name}/{self.ctx.name}/camera"
        self.renderer = _Renderer(self.width, self.height)

    def prepare(self, spec: mujoco.MjSpec) -> None:
        offscreen = spec.visual.global_
        offscreen.offwidth = max(offscreen.offwidth, self.width)
        offscreen.offheight = max(offscreen.offheight, self.height)
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
                self.image_pub.publish(self.image(now_ns, rgb))
        if self.info_pub.wanted:
            self.info_pub.publish(self.info(now_ns))

    def image(self, now_ns: int, rgb: npt.NDArray[Any]) -> Any:
        if self.encoding == "mono8":
            pixels = rgb.mean(axis=2).astype(np.uint8)
            step = self.width
        elif self.encoding == "bgr8":
            pixels, step = np.ascontiguousarray(rgb[:, :, ::-1]), self.width * 3
        else:
            pixels, step = rgb, self.width * 3
        return types().cls("sensor_msgs/Image")(
            build.header(now_ns, self.frame),
            self.height,
            self.width,
            self.encoding,
            0,
            step,
            np.ascontiguousarray(pixels).reshape(-1),
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


class ImuSensor(_Sensor):
    """``libgazebo_ros_imu_sensor.so`` on an ``imu`` sensor (and the model plugin
    ``libgazebo_ros_imu.so``): orientation, angular velocity and proper acceleration of the
    sensor frame, with gaussian noise."""

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        self.noise = self.number("gaussianNoise", 0.0)
        topic = self.text("topicName", "imu") or "imu"
        self.node = self.make_node()
        self.pub = self.node.publisher(topic, "sensor_msgs/Imu", queue_size=1)
        self.imu_type = types().cls("sensor_msgs/Imu")

    def update(self, now_ns: int) -> None:
        if not self.pub.wanted or not self.due(now_ns):
            return
        self.pub.publish(self.reading(now_ns))

    def reading(self, now_ns: int) -> Any:
        pose = self.world_pose()
        rotation = self.body_from_sensor[:3, :3]
        velocity = self.engine.body_velocity(self.body_id, local=True)
        acceleration = self.engine.body_acceleration(self.body_id)
        omega = rotation.T @ velocity[:3]
        accel = rotation.T @ acceleration[3:]
        if self.noise > 0:
            omega = omega + self.rng.normal(0.0, self.noise, 3)
            accel = accel + self.rng.normal(0.0, self.noise, 3)
        covariance = np.eye(3).reshape(-1) * self.noise * self.noise
        vector = types().cls("geometry_msgs/Vector3")
        quat = types().cls("geometry_msgs/Quaternion")(*quat_xyzw(pose))
        return self.imu_type(
            build.header(now_ns, self.frame),
            quat,
            covariance.copy(),
            vector(*map(float, omega)),
            covariance.copy(),
            vector(*map(float, accel)),
            covariance.copy(),
        )
