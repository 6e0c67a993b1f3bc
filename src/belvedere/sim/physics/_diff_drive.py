"""``libgazebo_ros_diff_drive.so``: a differential base driven through two wheel joints.

As the original (gazebo_ros_pkgs): the last ``cmd_vel`` persists; each update sets the wheel
joint velocities (limited by ``wheelTorque``; ``wheelAcceleration`` ramps with the original's
OR-condition quirk), after publishing odometry (``world``: the model's true pose and
velocity; ``encoder``: integrated from wheel speeds every step), the odom TF, wheel TFs and
wheel joint states as configured. ``legacyMode`` true swaps the wheels' roles as Gazebo 7 did
— the course's mbot, whose "left" wheel is on the right, needs it to turn the right way.
"""

from __future__ import annotations

import logging
import math

import numpy as np
import numpy.typing as npt

from belvedere.msgs import build
from belvedere.sim._odometry import publish_odometry
from belvedere.sim.physics._engine import planar_twist, quat_xyzw
from belvedere.sim.physics._motor import MotorDrive, VelocityMotor
from belvedere.sim.physics._plugin import PluginContext, RateGate
from belvedere.sim.physics._spec import ModelError
from belvedere.tf import TransformBroadcaster, resolve_tf

__all__ = ["DiffDrive"]

logger = logging.getLogger("belvedere.physics")

POSE_COVARIANCE = (1e-5, 1e-5, 1e12, 1e12, 1e12, 1e-3)


class DiffDrive(MotorDrive):
    NAMESPACE_DEFAULTS_TO_MODEL = True

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        if self.text("publishTf") is None:
            logger.warning(
                "%s: diff drive %r: <publishTf> missing, defaults to true",
                ctx.source,
                ctx.name,
            )
        self.command_topic = self.text("commandTopic", "cmd_vel") or "cmd_vel"
        self.odom_topic = self.text("odometryTopic", "odom") or "odom"
        odom_frame = self.text("odometryFrame", "odom") or "odom"
        base_frame = self.text("robotBaseFrame", "base_footprint") or ""
        self.base_link_name = base_frame.lstrip("/")
        self.publish_wheel_tf = self.flag("publishWheelTF", False)
        self.publish_odom_tf = self.flag("publishOdomTF", True)
        self.publish_tf = self.flag("publishTf", True)
        self.publish_joint_states = self.flag("publishWheelJointState", False)
        self.legacy = self.flag("legacyMode", False)
        self.separation = self.number("wheelSeparation", 0.34)
        self.diameter = self.number("wheelDiameter", 0.15)
        self.accel = self.number("wheelAcceleration", 0.0)
        self.torque = self.number("wheelTorque", 5.0)
        self.rate = self.number("updateRate", 100.0)
        source = self.text("odometrySource", "world") or "world"
        if source not in ("world", "encoder"):
            logger.error(
                "%s: odometrySource %r is neither 'world' nor 'encoder'; using 'world'",
                ctx.source,
                source,
            )
            source = "world"
        self.source = source
        self.left_joint = self.text("leftJoint", "left_joint") or "left_joint"
        self.right_joint = self.text("rightJoint", "right_joint") or "right_joint"
        for role, joint in (("leftJoint", self.left_joint), ("rightJoint", self.right_joint)):
            if joint not in self.robot.joints:
                known = ", ".join(sorted(self.robot.joints)) or "none"
                msg = f"diff drive {ctx.name!r}: <{role}> {joint!r} is not a movable joint"
                raise ModelError(msg, self._where(role), hint=f"movable joints: {known}")
        if self.diameter <= 0:
            msg = f"diff drive {ctx.name!r}: wheelDiameter must be positive"
            raise ModelError(msg, self._where("wheelDiameter"))
        if self.legacy:
            logger.info(
                "diff drive %r: legacyMode true: wheels as Gazebo 7 (Kinetic) drove them; "
                "Melodic and Noetic ignore legacyMode",
                ctx.name,
            )
        self.node = self.make_node()
        # As gazebo_ros_diff_drive: both frames through tf::resolve with the tf_prefix
        # searched from the plugin's namespace (robot_1/odom -> robot_1/base_footprint).
        self.odom_frame = resolve_tf(self.node, odom_frame)
        self.base_frame = resolve_tf(self.node, base_frame)
        joints = {j.name: j for j in self.robot.model.joints}
        # Gazebo reads tf_prefix once, at load: the wheel frames are named once too.
        self.wheel_frames = [
            (
                joints[name].parent,
                joints[name].child,
                resolve_tf(self.node, joints[name].parent),
                resolve_tf(self.node, joints[name].child),
            )
            for name in (self.left_joint, self.right_joint)
        ]
        self.node.subscribe(self.command_topic, "geometry_msgs/Twist", self._on_cmd, queue_size=1)
        self.odom_pub = (
            self.node.publisher(self.odom_topic, "nav_msgs/Odometry", queue_size=1)
            if self.publish_tf
            else None
        )
        self.tf = TransformBroadcaster(self.node)
        self.joint_pub = (
            self.node.publisher("joint_states", "sensor_msgs/JointState", queue_size=1000)
            if self.publish_joint_states
            else None
        )
        self.instructions = [0.0, 0.0]
        self.gate = RateGate(self.rate, ctx.graph.now_ns())
        self.pose_encoder = [0.0, 0.0, 0.0]
        self.encoder_twist = (0.0, 0.0)
        self.last_step_ns = ctx.graph.now_ns()
        self.covariance = np.zeros(36)
        self.covariance[[0, 7, 14, 21, 28, 35]] = POSE_COVARIANCE
        # Every odometry message shares it, read-only (rospy's covariances are tuples):
        # nobody can change another's, and it is not copied a hundred times a second.
        self.covariance.flags.writeable = False
        self.velocity = np.zeros(6)
        self.motors = [
            VelocityMotor(self._actuator(side), self.robot.joints[joint], self.torque)
            for side, joint in (("left", self.left_joint), ("right", self.right_joint))
        ]

    def joint_names(self) -> tuple[str, ...]:
        return (self.left_joint, self.right_joint) if self.publish_joint_states else ()

    # --- model ---------------------------------------------------------------------------------
    def _actuator(self, side: str) -> str:
        return f"{self.robot.name}/{self.ctx.name}/{side}"

    def bind(self) -> None:
        engine = self.engine
        self.bind_motors()
        self.joints = [
            engine.joint(self.robot.joints[self.left_joint]),
            engine.joint(self.robot.joints[self.right_joint]),
        ]
        self.wheel_dofs = (self.joints[0].dof, self.joints[1].dof)
        self.qvel = engine.d.qvel  # a view kept until the next compile (bind runs after it)
        link = self.base_link_name
        self.base_link = link if link in self.robot.link_body else None
        self.root_body = engine.body_id(self.robot.root_body)
        self.odom_body = (
            engine.frame_of(self.robot, self.base_link)
            if self.base_link is not None
            else (self.root_body, None)
        )
        self.wheel_bodies = [
            (engine.frame_of(self.robot, parent), engine.frame_of(self.robot, child))
            for parent, child, _, _ in self.wheel_frames
        ]

    def reset(self) -> None:
        self.instructions = [0.0, 0.0]
        self.pose_encoder = [0.0, 0.0, 0.0]
        self.last_step_ns = self.ctx.graph.now_ns()
        self.stop_motors()

    # --- stepping ------------------------------------------------------------------------------
    def next_update_ns(self, now_ns: int) -> int | None:
        return None if self.source == "encoder" else super().next_update_ns(now_ns)

    def update(self, now_ns: int) -> None:
        if self.source == "encoder":
            self._integrate_encoders(now_ns)
        due = self.gate.due(now_ns)
        if due:
            self._publish_odometry(now_ns)
            if self.publish_wheel_tf:
                self._publish_wheel_tf(now_ns)
            if self.joint_pub is not None:
                self._publish_joint_states(now_ns)
            self._set_wheels()
        self.apply_motors(now_ns, due=due)

    def _wheel_speeds(self) -> tuple[float, float]:
        half = self.rot * self.separation / 2.0
        if self.legacy:
            return (self.x + half, self.x - half)
        return (self.x - half, self.x + half)

    def _set_wheels(self) -> None:
        radius = self.diameter / 2.0
        targets = self._wheel_speeds()
        instructions = self.instructions
        if self.accel == 0:  # no ramp: the wheels' speeds do not matter
            for i, motor in enumerate(self.motors):
                instructions[i] = targets[i]
                motor.command(targets[i] / radius)
            return
        qvel, (left, right) = self.qvel, self.wheel_dofs
        current = (float(qvel[left]) * radius, float(qvel[right]) * radius)
        dt = self.gate.period_ns / 1e9 if self.gate.period_ns else self.engine.m.opt.timestep
        # Gazebo's quirk: either wheel near its target sets both to theirs.
        near = abs(targets[0] - current[0]) < 0.01 or abs(targets[1] - current[1]) < 0.01
        limit = self.accel * dt
        for i, motor in enumerate(self.motors):
            if near:
                instructions[i] = targets[i]
            else:
                instructions[i] += max(-limit, min(limit, targets[i] - current[i]))
            motor.command(instructions[i] / radius)

    def _integrate_encoders(self, now_ns: int) -> None:
        dt = (now_ns - self.last_step_ns) / 1e9
        self.last_step_ns = now_ns
        if dt <= 0:
            return
        d = self.engine.d
        radius = self.diameter / 2.0
        sl = float(d.qvel[self.joints[0].dof]) * radius * dt
        sr = float(d.qvel[self.joints[1].dof]) * radius * dt
        sdiff = (sl - sr) if self.legacy else (sr - sl)
        theta = self.pose_encoder[2]
        dx = (sl + sr) / 2.0 * math.cos(theta + sdiff / (2.0 * self.separation))
        dy = (sl + sr) / 2.0 * math.sin(theta + sdiff / (2.0 * self.separation))
        self.pose_encoder[0] += dx
        self.pose_encoder[1] += dy
        self.pose_encoder[2] += sdiff / self.separation
        self.encoder_twist = (math.hypot(dx, dy) / dt, sdiff / self.separation / dt)

    def _publish_odometry(self, now_ns: int) -> None:
        """The odom TF and odometry, from one read of the base's state — none when nobody
        listens to either."""
        send_tf = self.publish_tf and self.publish_odom_tf and self.tf.pub.wanted
        odom_pub = self.odom_pub if self.odom_pub is not None and self.odom_pub.wanted else None
        if not send_tf and odom_pub is None:
            return
        if self.source == "encoder":
            x, y, th = self.pose_encoder
            position = (x, y, 0.0)
            quat = (0.0, 0.0, math.sin(th / 2), math.cos(th / 2))
            v, w = self.encoder_twist
            linear = (v, 0.0, 0.0)
            angular = (0.0, 0.0, w)
        else:
            position, quat = self.engine.position_quat(*self.odom_body)
            qx, qy, qz, qw = quat
            yaw = math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
            velocity = self.engine.body_velocity(self.root_body, out=self.velocity)
            linear, angular = planar_twist(velocity, yaw)
        if send_tf:
            self.tf.send(self.odom_frame, self.base_frame, position, quat, now_ns)
        if odom_pub is not None:
            frames = (self.odom_frame, self.base_frame)
            publish_odometry(
                odom_pub,
                now_ns,
                frames,
                position,
                quat,
                linear,
                angular,
                pose_covariance=self.covariance,
            )

    def _publish_wheel_tf(self, now_ns: int) -> None:
        if not self.tf.pub.wanted:
            return
        d = self.engine.d
        transforms = []
        # Straight from the bodies' world poses: a hundred times a second per robot, where
        # 4x4 products and general inverses were a fifth of a many-robot world's time.
        for ((pb, p_off), (cb, c_off)), (_, _, pf, cf) in zip(
            self.wheel_bodies, self.wheel_frames, strict=True
        ):
            world_rp = d.xmat[pb].reshape(3, 3)
            rotation = world_rp.T @ d.xmat[cb].reshape(3, 3)
            translation = world_rp.T @ (d.xpos[cb] - d.xpos[pb])
            if p_off is not None or c_off is not None:
                rel = np.eye(4)
                rel[:3, :3], rel[:3, 3] = rotation, translation
                if p_off is not None:
                    rel = _rigid_inverse(p_off) @ rel
                if c_off is not None:
                    rel = rel @ c_off
                rotation, translation = rel[:3, :3], rel[:3, 3]
            transforms.append((pf, cf, translation, quat_xyzw(rotation)))
        self.tf.send_all(transforms, now_ns)

    def _publish_joint_states(self, now_ns: int) -> None:
        assert self.joint_pub is not None
        if not self.joint_pub.wanted:
            return
        d = self.engine.d
        positions = [float(d.qpos[j.qpos]) for j in self.joints]
        self.joint_pub.publish(
            build.joint_state(now_ns, [self.left_joint, self.right_joint], positions)
        )


def _rigid_inverse(t: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The inverse of a rotation-and-translation matrix (the transpose of its rotation)."""
    out = np.eye(4)
    rotation = t[:3, :3].T
    out[:3, :3] = rotation
    out[:3, 3] = -rotation @ t[:3, 3]
    return out
