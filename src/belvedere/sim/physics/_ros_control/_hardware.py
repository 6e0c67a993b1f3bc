"""The hardware interface's joints, as DefaultRobotHWSim holds them: state, a command for the
joint's interface, and control_toolbox's PID."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

from belvedere.graph import Graph, Node
from belvedere.sim.physics._engine import JointRef
from belvedere.sim.physics._motor import VelocityMotor
from belvedere.sim.physics._plugin import PluginContext

__all__ = ["ControllerHost", "JointHandle", "Pid", "RobotHardware"]


@dataclass
class Pid:
    """control_toolbox's PID: p, i, d, i_clamp (±), d on the error."""

    p: float
    i: float = 0.0
    d: float = 0.0
    i_clamp: float = 0.0
    integral: float = 0.0
    last_error: float | None = None

    @classmethod
    def from_params(cls, params: Any) -> Pid | None:
        if not isinstance(params, dict) or "p" not in params:
            return None
        clamp = max(
            abs(float(params.get("i_clamp", 0.0))), abs(float(params.get("i_clamp_max", 0.0)))
        )
        return cls(
            float(params["p"]), float(params.get("i", 0.0)), float(params.get("d", 0.0)), clamp
        )

    def __call__(self, error: float, dt: float) -> float:
        if dt <= 0:
            return 0.0
        self.integral += error * dt
        if self.i_clamp > 0 and self.i != 0:
            limit = self.i_clamp / abs(self.i)
            self.integral = max(-limit, min(limit, self.integral))
        derivative = 0.0 if self.last_error is None else (error - self.last_error) / dt
        self.last_error = error
        return self.p * error + self.i * self.integral + self.d * derivative

    def reset(self) -> None:
        self.integral = 0.0
        self.last_error = None


@dataclass
class JointHandle:
    """One joint as the hardware interface sees it: state, and a command for its interface."""

    name: str
    interface: str
    effort_limit: float
    velocity_limit: float
    lower: float | None
    upper: float | None
    ref: JointRef | None = None
    actuator: int = -1
    pid: Pid | None = None
    motor: VelocityMotor | None = None
    """A velocity joint without PID gains: Gazebo's joint motor."""
    command: float | None = None
    position: float = 0.0
    velocity: float = 0.0
    effort: float = 0.0
    claimed_by: str | None = None


class RobotHardware(Protocol):
    """What the controller manager uses of the plugin that holds it (``RosControl``); named
    here so that the manager's module need not import the plugin's, which imports it."""

    @property
    def ctx(self) -> PluginContext: ...

    def wheel_geometry(self, left: str, right: str) -> tuple[float, float]: ...


class ControllerHost(Protocol):
    """What a controller uses of its controller manager (``ControllerManager``); named here
    so that the controllers' modules need not import the manager's, which imports them."""

    @property
    def graph(self) -> Graph: ...
    @property
    def namespace(self) -> str: ...
    @property
    def node(self) -> Node: ...
    @property
    def handles(self) -> dict[str, JointHandle]: ...

    def wheel_geometry(self, left: str, right: str) -> tuple[float, float]: ...
