"""The driver's servo ``joints`` in fake mode: each moves towards its commanded position at
most ``max_speed`` per second, stepped at the driver's ``write_rate``.

Commands come from ``<joint>/command`` (``std_msgs/Float64``, ignored while a trajectory
controller drives the joint) or from a controller. Dynamixels also offer ``<joint>/relax``,
``<joint>/enable`` and ``<joint>/set_speed``; the servo group offers ``servos/relax_all`` and
``servos/enable_all``.
"""

from __future__ import annotations

import logging
from typing import Any, Protocol

from belvedere.graph import NS, Node
from belvedere.sim._commands import CommandGate
from belvedere.sim.kinematic._config import ServoConfig

__all__ = ["Servo", "ServoGroup"]

logger = logging.getLogger("belvedere.arbotix")


class _Controller(Protocol):
    def active(self) -> bool: ...


class Servo:
    """One fake servo. ``position`` is what ``joint_states`` reports."""

    def __init__(self, node: Node, config: ServoConfig) -> None:
        self.node = node
        self.config = config
        self.name = config.name
        self.dynamixel = config.type == "dynamixel"
        self.position = 0.0
        self.velocity = 0.0
        self.desired = 0.0
        self.last_cmd = 0.0
        self.dirty = False
        self.enabled = True
        self.active = not self.dynamixel  # hobby servos have no torque state
        self.controller: _Controller | None = None
        self.last_ns = node.now_ns()
        self.gate = CommandGate(node.resolve(f"{self.name}/command"), node.graph, logger)
        node.subscribe(f"{self.name}/command", "std_msgs/Float64", self.on_command)
        if self.dynamixel:
            node.service(f"{self.name}/relax", "arbotix_msgs/Relax", lambda _: self.relax())
            node.service(f"{self.name}/enable", "arbotix_msgs/Enable", self._on_enable)
            node.service(f"{self.name}/set_speed", "arbotix_msgs/SetSpeed", lambda _: {})

    def on_command(self, msg: Any) -> None:
        value = float(msg.data)
        if not self.gate.accept(other={"data": value}):
            return
        if not self.enabled:
            return
        if self.controller is not None and self.controller.active():
            return  # a trajectory is running: do not interfere (as the original)
        if self.desired != value or not self.active:
            self.dirty = True
            self.active = True
            self.desired = value

    def set_control_output(self, position: float) -> None:
        """A controller's target (the original's setControlOutput)."""
        if self.enabled:
            self.desired = position
            self.dirty = True
            self.active = True

    def interpolate(self, frame_hz: float) -> None:
        """One write cycle: step towards ``desired`` by at most ``max_speed / frame_hz``."""
        now = self.node.now_ns()
        if not (self.enabled and self.active and self.dirty):
            if self.dynamixel:
                self.velocity = 0.0
                self.last_ns = now
            return
        top = self.config.max_speed / frame_hz
        step = min(max(self.desired - self.last_cmd, -top), top)
        self.last_cmd = self.config.clamp(self.last_cmd + step)
        if self.last_cmd == self.desired:
            self.dirty = False
        previous = self.position
        self.position = self.last_cmd
        if self.dynamixel:
            dt = (now - self.last_ns) / NS
            self.velocity = (self.position - previous) / dt if dt > 0 else 0.0
            self.last_ns = now

    def reset(self) -> None:
        self.position = self.velocity = self.desired = self.last_cmd = 0.0
        self.dirty = False

    def relax(self) -> dict[str, Any]:
        self.dirty = False
        self.active = False
        return {}

    def _on_enable(self, request: Any) -> dict[str, Any]:
        if request.enable:
            self.enabled = True
        else:
            self.dirty = False
            self.enabled = False
            self.active = False
        return {"state": self.enabled}

    def diagnostics(self) -> dict[str, Any]:
        values = [{"key": "Position", "value": repr(self.position)}]
        if self.dynamixel:
            values += [
                {"key": "Temperature", "value": "0.0"},
                {"key": "Voltage", "value": "0.0"},
                {"key": "Reads", "value": "0.0"},
                {"key": "Error Rate", "value": "0.0%"},
                {"key": "Torque", "value": "ON" if self.active else "OFF"},
            ]
        return {"name": self.name, "level": 0, "message": "OK", "values": values}


class ServoGroup:
    """The driver's ``servos`` controller: steps every servo at ``write_rate``."""

    def __init__(self, node: Node, servos: list[Servo], write_rate: float) -> None:
        self.servos = servos
        self.write_rate = write_rate
        dynamixels = [s for s in servos if s.dynamixel]
        node.service("servos/relax_all", "arbotix_msgs/Relax", lambda _: self._relax(dynamixels))
        node.service(
            "servos/enable_all",
            "arbotix_msgs/Enable",
            lambda req: self._enable(dynamixels, req),
        )
        if servos:
            node.timer(1.0 / write_rate, self.update)

    def update(self) -> None:
        for servo in self.servos:
            servo.interpolate(self.write_rate)

    @staticmethod
    def _relax(servos: list[Servo]) -> dict[str, Any]:
        for servo in servos:
            servo.relax()
        return {}

    @staticmethod
    def _enable(servos: list[Servo], request: Any) -> dict[str, Any]:
        state = bool(request.enable)
        for servo in servos:
            state = bool(servo._on_enable(request)["state"])
        return {"state": state}
