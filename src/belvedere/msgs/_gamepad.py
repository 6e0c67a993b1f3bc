"""A gamepad's state as a browser page reads it through the Gamepad API (its id, axes from
-1 to 1 with up and left negative, buttons pressed or not), checked before anything uses it:
a page is the user's, but what it sends is only data.

The viewer's page hands the state on over the graph on :data:`GAMEPAD_TOPIC` as a
sensor_msgs/Joy of the browser's own values (``header.frame_id`` the pad's id); joy_node turns
them into ROS's (signs, dead zone, repeats). An empty message says no pad is connected."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any, Final

__all__ = [
    "GAMEPAD_TOPIC",
    "GAMEPAD_TYPE",
    "MAX_AXES",
    "MAX_BUTTONS",
    "MAX_ID",
    "GamepadState",
    "gamepad_from_json",
    "gamepad_from_msg",
    "gamepad_state",
]

GAMEPAD_TOPIC: Final = "/viewer/gamepad"
GAMEPAD_TYPE: Final = "sensor_msgs/Joy"
MAX_AXES: Final = 64
MAX_BUTTONS: Final = 128
"""The most a state may hold (the Gamepad API's standard mapping has 4 axes, 17 buttons)."""
MAX_ID: Final = 200
"""Characters of a pad's id kept (a browser gives name, vendor and product)."""
MAX_JSON: Final = 16_384
"""Bytes of a state as JSON: a full one of MAX_AXES and MAX_BUTTONS fits several times."""


@dataclass(frozen=True)
class GamepadState:
    """One look at a pad: ``axes`` as the browser gives them (clamped to [-1, 1]),
    ``buttons`` 0 or 1."""

    id: str
    axes: tuple[float, ...]
    buttons: tuple[int, ...]


def gamepad_state(pad_id: object, axes: object, buttons: object) -> GamepadState | None:
    """The state these values make, or None when they are not one (not lists, too long,
    an axis not a finite number, a button not 0 or 1, an id not text)."""
    if not isinstance(pad_id, str) or not isinstance(axes, list | tuple):
        return None
    if not isinstance(buttons, list | tuple):
        return None
    if len(axes) > MAX_AXES or len(buttons) > MAX_BUTTONS:
        return None
    values: list[float] = []
    for a in axes:
        if isinstance(a, bool) or not isinstance(a, int | float) or not math.isfinite(a):
            return None
        values.append(max(-1.0, min(1.0, float(a))))
    pressed: list[int] = []
    for b in buttons:
        if isinstance(b, bool) or b not in (0, 1):
            return None
        pressed.append(int(b))
    return GamepadState(pad_id[:MAX_ID], tuple(values), tuple(pressed))


def gamepad_from_json(text: str | bytes) -> GamepadState | None:
    """A state a page sent as JSON (``{"id", "axes", "buttons"}``; ``id`` may be left out),
    or None when the text is not one."""
    if len(text) > MAX_JSON:
        return None
    try:
        data: Any = json.loads(text)
    except ValueError:
        return None
    if not isinstance(data, dict):
        return None
    return gamepad_state(data.get("id", ""), data.get("axes"), data.get("buttons"))


def gamepad_from_msg(msg: Any) -> tuple[bool, GamepadState | None]:
    """(valid, state) of a sensor_msgs/Joy on :data:`GAMEPAD_TOPIC`: an empty one says no pad
    is connected (True, None); one that is not a state is (False, None) — any graph process
    may publish there."""
    axes = [float(a) for a in msg.axes]
    buttons = [int(b) for b in msg.buttons]
    if not axes and not buttons:
        return True, None
    state = gamepad_state(str(msg.header.frame_id), axes, buttons)
    return state is not None, state
