"""joy's ``joy_node``: a gamepad in the browser (the Gamepad API, on a page whose URL the
node prints; its port the ``~port`` parameter, 8093) published as sensor_msgs/Joy on ``joy``
— axes signed as ROS's joystick driver gives them (up and left positive), inside
``~deadzone`` (0.05) zero and rescaled beyond it; each change, and every 1/``~autorepeat_rate``
s while held when that is above 0."""

from __future__ import annotations

import sys

import numpy as np

from belvedere.graph import Node
from belvedere.msgs import build, types
from belvedere.nodes._joy_page import JoyPage
from belvedere.nodes._registry import (
    NodeSpec,
    Session,
    Starter,
    port_param,
    stopping_on_bad_values,
)

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE", "ros_axis"]

PACKAGE = "joy"
PORT = 8093


def ros_axis(value: float, deadzone: float) -> float:
    """A browser axis (-1 up/left) as joy_node's: its sign turned, the dead zone cut out
    and the rest stretched back to [-1, 1]."""
    if abs(value) <= deadzone:
        return 0.0
    magnitude = (abs(value) - deadzone) / (1.0 - deadzone)
    return -magnitude if value > 0 else magnitude


def _number(node: Node, name: str, default: float, low: float, high: float) -> float:
    value = node.get_param(f"~{name}", default)
    if isinstance(value, bool) or not isinstance(value, int | float) or not low <= value < high:
        msg = f"parameter ~{name}: expected a number from {low} to below {high}, got {value!r}"
        raise ValueError(msg)
    return float(value)


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    deadzone = _number(node, "deadzone", 0.05, 0.0, 1.0)
    repeat = _number(node, "autorepeat_rate", 0.0, 0.0, 1000.0)
    pub = node.publisher("joy", "sensor_msgs/Joy", queue_size=10)
    joy = types().cls("sensor_msgs/Joy")
    frame = str(node.get_param("~frame_id", "joy"))

    def on_state(axes: list[float], buttons: list[int]) -> None:
        values = np.array([ros_axis(a, deadzone) for a in axes], np.float32)
        pub.publish(joy(build.header(node.now_ns(), frame), values, np.array(buttons, np.int32)))

    page = JoyPage(on_state, port=port_param(node, PORT), repeat_hz=repeat)
    session.closers.append(page.close)
    node.set_param("~page_url", page.url)
    sys.stdout.write(f"joy_node: the gamepad's page is {page.url}\n")
    sys.stdout.flush()


EXECUTABLES: dict[str, Starter] = {"joy_node": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
