"""``libgazebo_ros_skid_steer_drive.so``: a base driven through four wheel joints, the two on
each side at the same speed.

As the original (gazebo_ros_pkgs): the last ``cmd_vel`` persists; each update (``updateRate``)
publishes odometry from the model's true pose and velocity (x and y of the pose, its full
orientation; the twist in the body's yaw frame), the ``odom`` TF when ``broadcastTF`` is set
(default false), and sets each wheel's velocity ``(x -+ rot * wheelSeparation / 2) / radius``
(left -, right +) within ``torque``. ``robotNamespace`` defaults to the root namespace.
"""

from __future__ import annotations

import logging

import numpy as np

from belvedere.sim._odometry import publish_odometry
from belvedere.sim.physics._engine import planar_twist, quat_xyzw, yaw_of
from belvedere.sim.physics._motor import MotorDrive, VelocityMotor
from belvedere.sim.physics._plugin import PluginContext, RateGate
from belvedere.sim.physics._spec import ModelError
from belvedere.tf import TransformBroadcaster

__all__ = ["SkidSteer"]

logger = logging.getLogger("belvedere.physics")

WHEELS = (
    ("leftFrontJoint", "left_front_joint", -1.0),
    ("rightFrontJoint", "right_front_joint", 1.0),
    ("leftRearJoint", "left_rear_joint", -1.0),
    ("rightRearJoint", "right_rear_joint", 1.0),
)
"""(parameter, default joint, side: -1 left, +1 right)."""

UNKNOWN = 1e12
"""The covariance the original gives z, roll and pitch."""


class SkidSteer(MotorDrive):
    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        self.command_topic = self.text("commandTopic", "cmd_vel") or "cmd_vel"
        self.odom_topic = self.text("odometryTopic", "odom") or "odom"
        self.odom_frame = (self.text("odometryFrame", "odom") or "odom").lstrip("/")
        self.base_frame = (self.text("robotBaseFrame", "base_footprint") or "").lstrip("/")
        self.broadcast_tf = self.flag("broadcastTF", False)
        self.separation = self.number("wheelSeparation", 0.4)
        self.diameter = self.number("wheelDiameter", 0.15)
        self.torque = self.number("torque", 5.0)
        self.rate = self.number("updateRate", 100.0)
        self.covariance = (
            self.number("covariance_x", 0.0001),
            self.number("covariance_y", 0.0001),
            self.number("covariance_yaw", 0.01),
        )
        if self.diameter <= 0:
            msg = f"skid steer drive {ctx.name!r}: wheelDiameter must be positive"
            raise ModelError(msg, self._where("wheelDiameter"))
        if self.torque < 0:
            msg = f"skid steer drive {ctx.name!r}: torque must not be negative"
            raise ModelError(msg, self._where("torque"))
        self.joints: list[tuple[str, float]] = []
        for tag, default, side in WHEELS:
            joint = self.text(tag, default) or default
            if joint not in self.robot.joints:
                known = ", ".join(sorted(self.robot.joints)) or "none"
                msg = f"skid steer drive {ctx.name!r}: <{tag}> {joint!r} is not a movable joint"
                raise ModelError(msg, self._where(tag), hint=f"movable joints: {known}")
            self.joints.append((joint, side))
        self.motors = [
            VelocityMotor(
                f"{self.robot.name}/{ctx.name}/{joint}", self.robot.joints[joint], self.torque
            )
            for joint, _ in self.joints
        ]
        self.node = self.make_node()
        self.node.subscribe(self.command_topic, "geometry_msgs/Twist", self._on_cmd, queue_size=1)
        self.odom_pub = self.node.publisher(self.odom_topic, "nav_msgs/Odometry", queue_size=1)
        self.tf = TransformBroadcaster(self.node)
        self.gate = RateGate(self.rate, ctx.graph.now_ns())

    # --- model ---------------------------------------------------------------------------------
    def bind(self) -> None:
        self.bind_motors()
        self.root_body = self.engine.body_id(self.robot.root_body)

    def reset(self) -> None:
        self.stop_motors()

    # --- stepping ------------------------------------------------------------------------------

    def update(self, now_ns: int) -> None:
        due = self.gate.due(now_ns)
        if due:
            self._publish_odometry(now_ns)
            radius = self.diameter / 2.0
            for motor, (_, side) in zip(self.motors, self.joints, strict=True):
                motor.command((self.x + side * self.rot * self.separation / 2.0) / radius)
        self.apply_motors(now_ns, due=due)

    def _publish_odometry(self, now_ns: int) -> None:
        pose = self.engine.body_pose(self.root_body)
        position = (float(pose[0, 3]), float(pose[1, 3]), 0.0)
        quat = quat_xyzw(pose)
        if self.broadcast_tf:
            transform = (float(pose[0, 3]), float(pose[1, 3]), float(pose[2, 3]))
            self.tf.send(self.odom_frame, self.base_frame, transform, quat, now_ns)
        if not self.odom_pub.wanted:
            return
        linear, angular = planar_twist(self.engine.body_velocity(self.root_body), yaw_of(pose))
        cx, cy, cyaw = self.covariance
        covariance = np.zeros(36)
        covariance[[0, 7, 14, 21, 28, 35]] = (cx, cy, UNKNOWN, UNKNOWN, UNKNOWN, cyaw)
        publish_odometry(
            self.odom_pub,
            now_ns,
            (self.odom_frame, self.base_frame),
            position,
            quat,
            linear,
            angular,
            pose_covariance=covariance,
            twist_covariance=covariance,
        )
