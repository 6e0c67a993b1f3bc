"""sensor_msgs/Joy to geometry_msgs/Twist, as teleop_twist_joy and turtlebot_teleop's
``turtlebot_teleop_joy`` do: axes times scales while the enable (deadman) button is held,
one stop when it is let go."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from belvedere.msgs import types

__all__ = ["JoyTwist", "axis_map", "twist"]

LINEAR = ("x", "y", "z")
ANGULAR = ("yaw", "pitch", "roll")
"""teleop_twist_joy's angular keys: yaw is about z, pitch about y, roll about x."""


def axis_map(value: object, name: str, default_key: str) -> dict[str, int]:
    """A parameter that is one axis number (for ``default_key``) or a map of them.

    Raises:
        ValueError: neither (naming the parameter).
    """
    if isinstance(value, int) and not isinstance(value, bool):
        return {default_key: value}
    if isinstance(value, Mapping) and all(
        isinstance(v, int) and not isinstance(v, bool) for v in value.values()
    ):
        return {str(k): int(v) for k, v in value.items()}
    msg = f"parameter ~{name}: expected an axis number or a map of them, got {value!r}"
    raise ValueError(msg)


def scale_map(value: object, name: str, default_key: str) -> dict[str, float]:
    if isinstance(value, int | float) and not isinstance(value, bool):
        return {default_key: float(value)}
    if isinstance(value, Mapping) and all(
        isinstance(v, int | float) and not isinstance(v, bool) for v in value.values()
    ):
        return {str(k): float(v) for k, v in value.items()}
    msg = f"parameter ~{name}: expected a number or a map of numbers, got {value!r}"
    raise ValueError(msg)


def _axis(joy: Any, axes: Mapping[str, int], scales: Mapping[str, float], key: str) -> float:
    index = axes.get(key)
    if index is None or key not in scales or not 0 <= index < len(joy.axes):
        return 0.0
    return float(joy.axes[index]) * scales[key]


def pressed(joy: Any, button: int) -> bool:
    return 0 <= button < len(joy.buttons) and bool(joy.buttons[button])


def twist(linear: tuple[float, float, float], angular: tuple[float, float, float]) -> Any:
    vector, twist_class = types().cls("geometry_msgs/Vector3"), types().cls("geometry_msgs/Twist")
    return twist_class(vector(*linear), vector(*angular))


@dataclass
class JoyTwist:
    """teleop_twist_joy's mapping (its parameters' meanings and defaults)."""

    enable_button: int = 0
    turbo_button: int = -1
    require_enable: bool = True
    axes_linear: dict[str, int] = field(default_factory=lambda: {"x": 1})
    scales_linear: dict[str, dict[str, float]] = field(default_factory=dict)
    axes_angular: dict[str, int] = field(default_factory=lambda: {"yaw": 0})
    scales_angular: dict[str, dict[str, float]] = field(default_factory=dict)
    sent_stop: bool = False

    def command(self, joy: Any) -> Any | None:
        """The Twist to send for ``joy``, or None (nothing to send)."""
        if pressed(joy, self.turbo_button):
            which = "turbo"
        elif not self.require_enable or pressed(joy, self.enable_button):
            which = "normal"
        else:
            if self.sent_stop:
                return None
            self.sent_stop = True
            return twist((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        self.sent_stop = False
        lin, ang = self.scales_linear[which], self.scales_angular[which]
        linear = tuple(_axis(joy, self.axes_linear, lin, k) for k in LINEAR)
        yaw, pitch, roll = (_axis(joy, self.axes_angular, ang, k) for k in ANGULAR)
        return twist((linear[0], linear[1], linear[2]), (roll, pitch, yaw))
