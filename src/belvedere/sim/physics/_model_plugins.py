"""Model plugins beyond the diff drive: ``libgazebo_ros_p3d.so`` (ground-truth odometry),
``libgazebo_ros_joint_state_publisher.so`` and ``libgazebo_ros_planar_move.so``."""

from __future__ import annotations

import logging
import math
from typing import Any

import numpy as np

from belvedere.msgs import build
from belvedere.sim._commands import CommandGate
from belvedere.sim._odometry import publish_odometry
from belvedere.sim.physics._engine import quat_xyzw, yaw_of
from belvedere.sim.physics._plugin import IDLE, Plugin, PluginContext, RateGate
from belvedere.sim.physics._spec import ModelError
from belvedere.tf import TransformBroadcaster

__all__ = ["GroundTruth", "JointStates", "PlanarMove"]

logger = logging.getLogger("belvedere.physics")


class GroundTruth(Plugin):
    """``libgazebo_ros_p3d.so``: a link's true pose and velocity as ``nav_msgs/Odometry``."""

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        body = self.text("bodyName")
        if body is None or body not in self.robot.link_body:
            msg = f"p3d plugin {ctx.name!r}: <bodyName> {body!r} is not a link of the robot"
            raise ModelError(msg, self._where("bodyName"))
        self.link = body
        self.frame = (self.text("frameName", "world") or "world").lstrip("/")
        self.offset_xyz = self._triple("xyzOffsets") or self._triple("xyzOffset")
        self.noise = self.number("gaussianNoise", 0.0)
        self.gate = RateGate(self.number("updateRate", 0.0), ctx.graph.now_ns())
        self.node = self.make_node()
        self.pub = self.node.publisher(
            self.text("topicName", "odom") or "odom", "nav_msgs/Odometry", queue_size=10
        )

    def _triple(self, tag: str) -> tuple[float, float, float] | None:
        text = self.text(tag)
        if not text:
            return None
        try:
            x, y, z = (float(v) for v in text.split())
        except ValueError:
            msg = f"p3d plugin {self.ctx.name!r}: <{tag}> expects 3 numbers, got {text!r}"
            raise ModelError(msg, self._where(tag)) from None
        return (x, y, z)

    def bind(self) -> None:
        self.body_id = self.engine.body_id(self.robot.body_of(self.link))

    def next_update_ns(self, now_ns: int) -> int | None:
        return self.gate.next_ns() if self.pub.wanted else IDLE

    def update(self, now_ns: int) -> None:
        if not self.pub.wanted or not self.gate.due(now_ns):
            return
        pose = self.engine.link_pose(self.robot, self.link)
        position = pose[:3, 3] + np.asarray(self.offset_xyz or (0.0, 0.0, 0.0))
        vel = self.engine.body_velocity(self.body_id)
        linear, angular = vel[3:], vel[:3]
        if self.noise > 0:
            position = position + self.rng.normal(0.0, self.noise, 3)
            linear = linear + self.rng.normal(0.0, self.noise, 3)
            angular = angular + self.rng.normal(0.0, self.noise, 3)
        variance = [self.noise**2] * 6
        covariance = np.diag(variance).reshape(-1)
        publish_odometry(
            self.pub,
            now_ns,
            (self.frame, self.link),
            position,
            quat_xyzw(pose),
            linear,
            angular,
            pose_covariance=covariance,
            twist_covariance=covariance,
        )


class JointStates(Plugin):
    """``libgazebo_ros_joint_state_publisher.so``: the listed joints on ``joint_states``."""

    NAMESPACE_DEFAULTS_TO_MODEL = True

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        names = [n.strip() for n in (self.text("jointName") or "").split(",") if n.strip()]
        for name in names:
            if name not in self.robot.joints:
                known = ", ".join(sorted(self.robot.joints)) or "none"
                msg = f"joint_state_publisher plugin: {name!r} is not a movable joint"
                raise ModelError(msg, self._where("jointName"), hint=f"movable joints: {known}")
        self.names = names
        self.gate = RateGate(self.number("updateRate", 100.0), ctx.graph.now_ns())
        self.node = self.make_node()
        self.pub = self.node.publisher("joint_states", "sensor_msgs/JointState", queue_size=1000)

    def joint_names(self) -> tuple[str, ...]:
        return tuple(self.names)

    def bind(self) -> None:
        self.refs = [self.engine.joint(self.robot.joints[n]) for n in self.names]

    def next_update_ns(self, now_ns: int) -> int | None:
        return self.gate.next_ns() if self.pub.wanted else IDLE

    def update(self, now_ns: int) -> None:
        if not self.pub.wanted or not self.gate.due(now_ns):
            return
        d = self.engine.d
        self.pub.publish(
            build.joint_state(
                now_ns,
                self.names,
                [float(d.qpos[r.qpos]) for r in self.refs],
                [float(d.qvel[r.dof]) for r in self.refs],
                [float(d.qfrc_actuator[r.dof]) for r in self.refs],
            )
        )


class PlanarMove(Plugin):
    """``libgazebo_ros_planar_move.so``: the model's velocity set directly in its yaw frame
    (x, y, turn) every step; odometry from its true pose."""

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        if self.robot.free_joint is None:
            msg = f"planar_move plugin {ctx.name!r}: the robot is fixed to the world"
            raise ModelError(msg, ctx.source)
        self.odom_frame = (self.text("odometryFrame", "odom") or "odom").lstrip("/")
        self.base_frame = (self.text("robotBaseFrame", "base_footprint") or "").lstrip("/")
        self.publish_tf = self.flag("publishOdometryTf", True)
        self.gate = RateGate(self.number("odometryRate", 20.0), ctx.graph.now_ns())
        self.node = self.make_node()
        self.node.subscribe(
            self.text("commandTopic", "cmd_vel") or "cmd_vel",
            "geometry_msgs/Twist",
            self._on_cmd,
            queue_size=1,
        )
        self.odom_pub = self.node.publisher(
            self.text("odometryTopic", "odom") or "odom", "nav_msgs/Odometry", queue_size=1
        )
        self.tf = TransformBroadcaster(self.node)
        self.command = (0.0, 0.0, 0.0)
        self.commands = CommandGate(self.ctx.name, ctx.graph, logger)

    def _on_cmd(self, msg: Any) -> None:
        x, y, rot = float(msg.linear.x), float(msg.linear.y), float(msg.angular.z)
        linear = {"linear.x": x, "linear.y": y}
        if not self.commands.accept(linear=linear, angular={"angular.z": rot}):
            return
        self.command = (x, y, rot)

    def bind(self) -> None:
        assert self.robot.free_joint is not None
        self.joint = self.engine.joint(self.robot.free_joint)

    def reset(self) -> None:
        self.command = (0.0, 0.0, 0.0)

    def update(self, now_ns: int) -> None:
        d = self.engine.d
        pose = self.engine.link_pose(self.robot, self.robot.model.root_link.name)
        yaw = yaw_of(pose)
        x, y, rot = self.command
        dof = self.joint.dof
        # free joint velocity: linear in the world frame, angular in the body frame
        d.qvel[dof] = x * math.cos(yaw) - y * math.sin(yaw)
        d.qvel[dof + 1] = y * math.cos(yaw) + x * math.sin(yaw)
        d.qvel[dof + 2] = 0.0
        body_rotation = self.engine.body_pose(self.engine.body_id(self.robot.root_body))[:3, :3]
        d.qvel[dof + 3 : dof + 6] = body_rotation.T @ np.array([0.0, 0.0, rot])
        if not self.gate.due(now_ns):
            return
        position = pose[:3, 3]
        quat = quat_xyzw(pose)
        if self.publish_tf:
            self.tf.send(self.odom_frame, self.base_frame, position, quat, now_ns)
        frames = (self.odom_frame, self.base_frame)
        twist = ((x, y, 0.0), (0.0, 0.0, rot))
        publish_odometry(self.odom_pub, now_ns, frames, position, quat, *twist)
