"""diff_drive_controller: wheel velocities from ``cmd_vel``, odometry from wheel positions."""

from __future__ import annotations

import logging
import math
from typing import Any

from belvedere.graph import NS
from belvedere.sim._commands import CommandGate
from belvedere.sim._odometry import publish_odometry
from belvedere.sim.physics._plugin import RateGate
from belvedere.sim.physics._ros_control._controllers import Controller
from belvedere.sim.physics._ros_control._hardware import ControllerHost
from belvedere.sim.physics._spec import ModelError
from belvedere.tf import TransformBroadcaster

__all__ = ["DiffDriveController"]

logger = logging.getLogger("belvedere.ros_control")


class DiffDriveController(Controller):
    """diff_drive_controller/DiffDriveController (velocity joints): ``cmd_vel`` with a
    timeout, odometry integrated "exactly" from wheel positions, ``odom`` and its TF."""

    interface = "velocity"

    def __init__(self, manager: ControllerHost, name: str, params: dict[str, Any]) -> None:
        super().__init__(manager, name, params)
        self.left = _names(params.get("left_wheel"), name, "left_wheel")
        self.right = _names(params.get("right_wheel"), name, "right_wheel")
        self.separation = float(params.get("wheel_separation", 0.0)) * float(
            params.get("wheel_separation_multiplier", 1.0)
        )
        self.radius = float(params.get("wheel_radius", 0.0)) * float(
            params.get("wheel_radius_multiplier", 1.0)
        )
        if self.separation <= 0 or self.radius <= 0:
            sep, rad = manager.wheel_geometry(self.left[0], self.right[0])
            self.separation = self.separation or sep
            self.radius = self.radius or rad
        self.timeout_ns = round(float(params.get("cmd_vel_timeout", 0.5)) * NS)
        rate = float(params.get("publish_rate", 50.0))
        self.publish_gate = RateGate(rate, manager.graph.now_ns(), strict=False, immediate=True)
        self.base_frame = str(params.get("base_frame_id", "base_link"))
        self.odom_frame = str(params.get("odom_frame_id", "odom"))
        self.enable_tf = bool(params.get("enable_odom_tf", True))
        self.pose_cov = _diagonal(params.get("pose_covariance_diagonal"))
        self.twist_cov = _diagonal(params.get("twist_covariance_diagonal"))
        self.limits = (
            params.get("linear", {}).get("x", {}) if isinstance(params.get("linear"), dict) else {}
        )
        self.angular_limits = (
            params.get("angular", {}).get("z", {})
            if isinstance(params.get("angular"), dict)
            else {}
        )
        self.cmd = (0.0, 0.0)
        self.cmd_ns = 0
        self.x = self.y = self.heading = 0.0
        self.last_wheels: tuple[float, float] | None = None
        self.velocity = (0.0, 0.0)
        self.gate = CommandGate(self.node.resolve("~cmd_vel"), manager.graph, logger)
        self.node.subscribe("~cmd_vel", "geometry_msgs/Twist", self._on_cmd, queue_size=1)
        self.odom_pub = self.node.publisher("~odom", "nav_msgs/Odometry", queue_size=100)
        self.tf = TransformBroadcaster(self.node)

    def joints(self) -> list[str]:
        return [*self.left, *self.right]

    def _on_cmd(self, msg: Any) -> None:
        v, w = float(msg.linear.x), float(msg.angular.z)
        if not self.gate.accept(linear={"linear.x": v}, angular={"angular.z": w}):
            return
        self.cmd = (_limit(v, self.limits), _limit(w, self.angular_limits))
        self.cmd_ns = self.node.now_ns()

    def update(self, now_ns: int, dt: float) -> None:
        left = sum(self.handle(j).position for j in self.left) / len(self.left)
        right = sum(self.handle(j).position for j in self.right) / len(self.right)
        if self.last_wheels is not None and dt > 0:
            dl = (left - self.last_wheels[0]) * self.radius
            dr = (right - self.last_wheels[1]) * self.radius
            linear, angular = (dl + dr) / 2, (dr - dl) / self.separation
            if abs(angular) < 1e-6:  # RK2
                direction = self.heading + angular / 2
                self.x += linear * math.cos(direction)
                self.y += linear * math.sin(direction)
                self.heading += angular
            else:  # exact arc
                r = linear / angular
                new_heading = self.heading + angular
                self.x += r * (math.sin(new_heading) - math.sin(self.heading))
                self.y -= r * (math.cos(new_heading) - math.cos(self.heading))
                self.heading = new_heading
            self.velocity = (linear / dt, angular / dt)
        self.last_wheels = (left, right)
        v, w = self.cmd if now_ns - self.cmd_ns <= self.timeout_ns else (0.0, 0.0)
        left_speed = (v - w * self.separation / 2) / self.radius
        right_speed = (v + w * self.separation / 2) / self.radius
        for j in self.left:
            self.handle(j).command = left_speed
        for j in self.right:
            self.handle(j).command = right_speed
        if not self.publish_gate.due(now_ns):
            return
        quat = (0.0, 0.0, math.sin(self.heading / 2), math.cos(self.heading / 2))
        position = (self.x, self.y, 0.0)
        publish_odometry(
            self.odom_pub,
            now_ns,
            (self.odom_frame, self.base_frame),
            position,
            quat,
            (self.velocity[0], 0.0, 0.0),
            (0.0, 0.0, self.velocity[1]),
            pose_covariance=self.pose_cov,
            twist_covariance=self.twist_cov,
        )
        if self.enable_tf:
            self.tf.send(self.odom_frame, self.base_frame, position, quat, now_ns)


def _limit(value: float, limits: dict[str, Any]) -> float:
    if limits.get("has_velocity_limits"):
        top = float(limits.get("max_velocity", math.inf))
        bottom = float(limits.get("min_velocity", -top))
        return min(max(value, bottom), top)
    return value


def _diagonal(values: Any) -> list[float] | None:
    if not isinstance(values, list) or len(values) != 6:
        return None
    out = [0.0] * 36
    for i, v in enumerate(values):
        out[i * 7] = float(v)
    return out


def _names(value: Any, controller: str, key: str) -> list[str]:
    if isinstance(value, str):
        return [value]
    if isinstance(value, list) and value and all(isinstance(v, str) for v in value):
        return list(value)
    msg = f"controller {controller!r}: {key!r} must name a wheel joint (or a list of them)"
    raise ModelError(msg)
