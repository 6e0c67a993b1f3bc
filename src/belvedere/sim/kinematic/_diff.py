"""``diff_controller`` in fake mode: a differential base that moves exactly as commanded.

As the original: ``cmd_vel`` sets the forward speed ``dx`` and turn rate ``dr`` at once (no
acceleration limit; other Twist components are ignored); every ``1/rate`` seconds the pose is
integrated with explicit Euler over the elapsed time — position first, then heading, which is
never wrapped — and published as ``odom`` and the ``odom → base_frame_id`` transform. The
original's ``timeout`` never stops a fake base; ``cmd_vel_timeout`` (ours) does.
"""

from __future__ import annotations

import logging
import math
from typing import Any

from belvedere.graph import NS, Node
from belvedere.sim._commands import CommandGate
from belvedere.sim._odometry import publish_odometry
from belvedere.sim.kinematic._config import DiffControllerConfig
from belvedere.tf import TransformBroadcaster

__all__ = ["DiffController"]

logger = logging.getLogger("belvedere.arbotix")


class DiffController:
    """The fake differential base of one ArbotiX driver node."""

    joint_names = ("base_l_wheel_joint", "base_r_wheel_joint")
    """The original's placeholder joints on ``joint_states`` (always 0)."""

    def __init__(self, node: Node, config: DiffControllerConfig, *, frame_prefix: str = "") -> None:
        self.node = node
        self.config = config
        self.name = config.name
        self.base_frame = frame_prefix + config.base_frame_id
        self.odom_frame = frame_prefix + config.odom_frame_id
        self.x = 0.0
        self.y = 0.0
        self.th = 0.0
        self.dx = 0.0
        self.dr = 0.0
        now = node.now_ns()
        self.then_ns = now
        self.last_cmd_ns = now
        self.gate = CommandGate(node.resolve("cmd_vel"), node.graph, logger)
        node.subscribe("cmd_vel", "geometry_msgs/Twist", self.on_cmd_vel, queue_size=10)
        self.odom_pub = node.publisher("odom", "nav_msgs/Odometry", queue_size=5, seq_rule="rospy")
        self.tf = TransformBroadcaster(node)
        node.timer(1.0 / config.rate, self.update)
        logger.info(
            "Started DiffController (%s). Geometry: %sm wide, %s ticks/m.",
            self.name,
            config.base_width,
            config.ticks_meter,
        )

    @property
    def joint_positions(self) -> tuple[float, ...]:
        return (0.0, 0.0)

    @property
    def joint_velocities(self) -> tuple[float, ...]:
        return (0.0, 0.0)

    def on_cmd_vel(self, msg: Any) -> None:
        dx = float(msg.linear.x)
        dr = float(msg.angular.z)
        if not self.gate.accept(linear={"linear.x": dx}, angular={"angular.z": dr}):
            return
        self.last_cmd_ns = self.node.now_ns()
        self.dx = dx
        self.dr = dr

    def update(self) -> None:
        now = self.node.now_ns()
        timeout = self.config.cmd_vel_timeout
        if timeout > 0 and now - self.last_cmd_ns > timeout * NS:
            self.dx = self.dr = 0.0
        elapsed = (now - self.then_ns) / NS
        self.then_ns = now
        self.x += math.cos(self.th) * self.dx * elapsed
        self.y += math.sin(self.th) * self.dx * elapsed
        self.th += self.dr * elapsed
        quat = (0.0, 0.0, math.sin(self.th / 2), math.cos(self.th / 2))
        position = (self.x, self.y, 0.0)
        self.tf.send(self.odom_frame, self.base_frame, position, quat, now)
        frames = (self.odom_frame, self.base_frame)
        twist = ((self.dx, 0.0, 0.0), (0.0, 0.0, self.dr))
        publish_odometry(self.odom_pub, now, frames, position, quat, *twist)

    def reset(self) -> None:
        """Back to the origin, stopped (the viewer's Reset)."""
        self.x = self.y = self.th = self.dx = self.dr = 0.0
        self.then_ns = self.last_cmd_ns = self.node.now_ns()

    def diagnostics(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "level": 0,
            "message": "OK",
            "values": [
                {"key": "dX", "value": repr(self.dx)},
                {"key": "dR", "value": repr(self.dr)},
            ],
        }
