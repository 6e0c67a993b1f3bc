"""``arbotix_driver`` with ``sim: true``: servos and controllers with no hardware behind them.

The driver publishes ``joint_states`` (servo positions, then each controller's joints) at
``read_rate`` and ``diagnostics`` at ``diagnostic_rate``; servos step at ``write_rate`` and
each controller runs at its own ``rate``. The original polls all of these from one loop at
``rate`` Hz with ``now > t_next``, which stretches each period by up to one loop tick (about
9.1-10 Hz for a 10 Hz controller); here each fires exactly at its rate in graph time.
"""

from __future__ import annotations

import logging
from typing import Any

from belvedere.graph import Node
from belvedere.msgs import build, message_from_data
from belvedere.sim.kinematic._config import (
    ArbotixConfig,
    DiffControllerConfig,
    FollowControllerConfig,
    param_locator,
)
from belvedere.sim.kinematic._diff import DiffController
from belvedere.sim.kinematic._follow import FollowController
from belvedere.sim.kinematic._servos import Servo, ServoGroup

__all__ = ["ArbotixDriver"]

logger = logging.getLogger("belvedere.arbotix")


class ArbotixDriver:
    """One fake ArbotiX board on ``node`` (usually named ``arbotix``).

    ``config`` defaults to the node's private parameters. ``frame_prefix`` (ours) prefixes the
    TF frames, for several robots in one graph."""

    def __init__(
        self, node: Node, config: ArbotixConfig | None = None, *, frame_prefix: str = ""
    ) -> None:
        self.node = node
        if config is None:
            config = ArbotixConfig.from_params(
                node.get_param("~", {}), locate=param_locator(node.full_name)
            )
        self.config = config
        if not config.sim:
            logger.warning(
                "%s: sim is false, but belvedere has no ArbotiX hardware support: simulating",
                node.full_name,
            )
        for skipped in config.skipped:
            logger.warning("%s: controller %s skipped", node.full_name, skipped)
        self.servos = {c.name: Servo(node, c) for c in config.joints}
        self.servo_group = ServoGroup(node, list(self.servos.values()), config.write_rate)
        self.controllers: list[DiffController | FollowController] = []
        for c in config.controllers:
            if isinstance(c, DiffControllerConfig):
                self.controllers.append(DiffController(node, c, frame_prefix=frame_prefix))
            elif isinstance(c, FollowControllerConfig):
                self.controllers.append(FollowController(node, c, self.servos))
        for name in ("SetupAnalogIn", "SetupDigitalIn", "SetupDigitalOut"):
            node.service(f"~{name}", "arbotix_msgs/SetupChannel", lambda _: {})
        self.joint_pub = node.publisher(
            "joint_states", "sensor_msgs/JointState", queue_size=5, seq_rule="rospy"
        )
        self.diag_pub = node.publisher(
            "diagnostics", "diagnostic_msgs/DiagnosticArray", seq_rule="rospy"
        )
        node.timer(1.0 / config.read_rate, self.publish_joint_states)
        node.timer(1.0 / config.diagnostic_rate, self.publish_diagnostics)
        logger.info("ArbotiX being simulated.")

    @property
    def base(self) -> DiffController | None:
        """The first differential base, if any."""
        return next((c for c in self.controllers if isinstance(c, DiffController)), None)

    def reset(self) -> None:
        """Every controller and servo back to its start (stopped, at zero)."""
        for controller in self.controllers:
            controller.reset()
        for servo in self.servos.values():
            servo.reset()

    def publish_joint_states(self) -> None:
        if not self.joint_pub.wanted:
            return
        names: list[str] = []
        positions: list[float] = []
        velocities: list[float] = []
        for servo in self.servos.values():
            names.append(servo.name)
            positions.append(servo.position)
            velocities.append(servo.velocity)
        for controller in self.controllers:
            names += controller.joint_names
            positions += controller.joint_positions
            velocities += controller.joint_velocities
        self.joint_pub.publish(build.joint_state(self.node.now_ns(), names, positions, velocities))

    def publish_diagnostics(self) -> None:
        if not self.diag_pub.wanted:
            return
        status: list[dict[str, Any]] = [c.diagnostics() for c in self.controllers]
        status += [s.diagnostics() for s in self.servos.values()]
        now = self.node.now_ns()
        self.diag_pub.publish(
            message_from_data(
                "diagnostic_msgs/DiagnosticArray",
                {
                    "header": {"stamp": [now // 1_000_000_000, now % 1_000_000_000]},
                    "status": status,
                },
            )
        )
