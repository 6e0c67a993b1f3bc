"""turtlebot_teleop's ``turtlebot_teleop_joy``: ``joy`` to ``~cmd_vel`` at 10 Hz while the
deadman button (``~axis_deadman``, 4) is held — ``~axis_linear`` (1) times ``~scale_linear``
(0.1), ``~axis_angular`` (0) times ``~scale_angular`` (1.0) — and one stop when let go."""

from __future__ import annotations

from typing import Any

from belvedere.graph import Node
from belvedere.nodes._joy_teleop import pressed, twist
from belvedere.nodes._registry import NodeSpec, Session, Starter, stopping_on_bad_values

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "turtlebot_teleop"


def _number(node: Node, name: str, default: float, *, whole: bool = False) -> float:
    value = node.get_param(f"~{name}", default)
    kinds = int if whole else int | float
    if isinstance(value, bool) or not isinstance(value, kinds):
        wanted = "an axis or button number" if whole else "a number"
        msg = f"parameter ~{name}: expected {wanted}, got {value!r}"
        raise ValueError(msg)
    return float(value)


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    deadman = int(_number(node, "axis_deadman", 4, whole=True))
    linear_axis = int(_number(node, "axis_linear", 1, whole=True))
    angular_axis = int(_number(node, "axis_angular", 0, whole=True))
    linear_scale = _number(node, "scale_linear", 0.1)
    angular_scale = _number(node, "scale_angular", 1.0)
    # its own ~cmd_vel, latched, as the original advertises it
    pub = node.publisher("~cmd_vel", "geometry_msgs/Twist", queue_size=1, latch=True)
    state: dict[str, Any] = {"last": None, "held": False, "was_held": False}

    def axis(joy: Any, index: int) -> float:
        return float(joy.axes[index]) if 0 <= index < len(joy.axes) else 0.0

    def on_joy(joy: Any) -> None:
        state["last"] = twist(
            (linear_scale * axis(joy, linear_axis), 0.0, 0.0),
            (0.0, 0.0, angular_scale * axis(joy, angular_axis)),
        )
        state["held"] = pressed(joy, deadman)

    def tick() -> None:
        if state["held"] and state["last"] is not None:
            pub.publish(state["last"])
        elif state["was_held"]:
            pub.publish(twist((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
        state["was_held"] = state["held"]

    node.subscribe("joy", "sensor_msgs/Joy", on_joy, queue_size=10)
    node.timer(0.1, tick)


EXECUTABLES: dict[str, Starter] = {"turtlebot_teleop_joy": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
