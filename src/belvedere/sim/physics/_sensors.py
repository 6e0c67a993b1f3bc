"""Gazebo's sensors with their ROS plugins: ``ray``/``gpu_ray`` + the laser plugins,
``imu`` + ``libgazebo_ros_imu_sensor.so``, and what every sensor plugin shares (its frame,
rate and laziness); the cameras are in :mod:`._cameras`.

Sensors are lazy: nothing is cast or rendered while nobody subscribes. A laser scan is one
``mj_multiRay`` against collision geometry. Noise is gaussian from the simulation's seed.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import Pose, XmlData, transform
from belvedere.graph import Node
from belvedere.msgs import build, types
from belvedere.sim.physics._engine import quat_xyzw
from belvedere.sim.physics._plugin import IDLE, Plugin, PluginContext, RateGate
from belvedere.sim.physics._spec import RAY_GROUPS, ModelError
from belvedere.tf import resolve_tf

__all__ = ["ImuSensor", "LaserSensor", "sensor_pose"]

Matrix4 = npt.NDArray[np.float64]


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
        self.frame_name = self.text("frameName") or self.link
        self.frame = self.frame_name.lstrip("/")

    def make_node(self, suffix: str = "") -> Node:
        """Its node, and its frame resolved as the ROS plugins resolve ``frameName``: with
        the ``tf_prefix`` found from the node's namespace (robot_1/laser_link)."""
        node = super().make_node(suffix)
        self.frame = resolve_tf(node, self.frame_name)
        return node

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

    def wanted(self) -> bool:
        """Whether anyone listens to what the sensor publishes."""
        return True

    def next_update_ns(self, now_ns: int) -> int | None:
        if not self.wanted():
            return IDLE
        return self.gate.next_ns()


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
        self.group[list(RAY_GROUPS)] = 1
        self.geomid = np.zeros(self.count, dtype=np.int32)
        self.dist = np.zeros(self.count, dtype=np.float64)
        self.scan_type = types().cls("sensor_msgs/LaserScan")

    def wanted(self) -> bool:
        return self.pub.wanted

    def update(self, now_ns: int) -> None:
        if not self.wanted() or not self.due(now_ns):
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
        d = self.dist
        if self.noise_std > 0 or self.noise_mean != 0:
            out = d + self.rng.normal(self.noise_mean, self.noise_std, self.count)
        else:
            out = d.copy()
        np.clip(out, self.range_min, self.range_max, out=out)
        # A miss (MuJoCo's -1) or a range at or past max reads +inf, a hit at or below min
        # -inf (REP 117); noise is drawn for every beam, hit or not, so the stream stays put.
        out[(d >= self.range_max) | (self.geomid < 0)] = np.inf
        out[(d <= self.range_min) & (self.geomid >= 0)] = -np.inf
        return out

    def scan(self, now_ns: int) -> Any:
        ranges = self.ranges().astype(np.float32)
        return self.scan_type(
            build.header(now_ns, self.frame, self.pub.next_seq()),
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

    def wanted(self) -> bool:
        return self.pub.wanted

    def update(self, now_ns: int) -> None:
        if not self.wanted() or not self.due(now_ns):
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
