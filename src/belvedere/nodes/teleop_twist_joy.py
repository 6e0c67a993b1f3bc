"""teleop_twist_joy's ``teleop_node``: ``joy`` (sensor_msgs/Joy) to ``cmd_vel`` with its
parameters (``~enable_button``, ``~enable_turbo_button``, ``~axis_linear``/``~axis_angular``
as one axis or a map, ``~scale_*`` and ``~scale_*_turbo``, ``~require_enable_button``)."""

from __future__ import annotations

from typing import Any

from belvedere.graph import Node
from belvedere.nodes._joy_teleop import JoyTwist, axis_map, scale_map
from belvedere.nodes._registry import NodeSpec, Session, Starter, stopping_on_bad_values

__all__ = ["EXECUTABLES", "JOINING", "NAMES", "PACKAGE"]

PACKAGE = "teleop_twist_joy"


def _button(node: Node, name: str, default: int) -> int:
    value = node.get_param(f"~{name}", default)
    if isinstance(value, bool) or not isinstance(value, int):
        msg = f"parameter ~{name}: expected a button number, got {value!r}"
        raise ValueError(msg)
    return value


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    require = node.get_param("~require_enable_button", True)
    if not isinstance(require, bool):
        msg = f"parameter ~require_enable_button: expected true or false, got {require!r}"
        raise ValueError(msg)
    mapping = JoyTwist(
        enable_button=_button(node, "enable_button", 0),
        turbo_button=_button(node, "enable_turbo_button", -1),
        require_enable=require,
        axes_linear=axis_map(node.get_param("~axis_linear", 1), "axis_linear", "x"),
        axes_angular=axis_map(node.get_param("~axis_angular", 0), "axis_angular", "yaw"),
        scales_linear={
            "normal": scale_map(node.get_param("~scale_linear", 0.5), "scale_linear", "x"),
            "turbo": scale_map(
                node.get_param("~scale_linear_turbo", 1.0), "scale_linear_turbo", "x"
            ),
        },
        scales_angular={
            "normal": scale_map(node.get_param("~scale_angular", 0.5), "scale_angular", "yaw"),
            "turbo": scale_map(
                node.get_param("~scale_angular_turbo", 1.0), "scale_angular_turbo", "yaw"
            ),
        },
    )
    pub = node.publisher("cmd_vel", "geometry_msgs/Twist", queue_size=1)

    def on_joy(joy: Any) -> None:
        command = mapping.command(joy)
        if command is not None:
            pub.publish(command)

    node.subscribe("joy", "sensor_msgs/Joy", on_joy, queue_size=1)


EXECUTABLES: dict[str, Starter] = {"teleop_node": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
NAMES = {"teleop_node": "teleop_twist_joy_node"}
"""Its ``ros::init`` name."""
