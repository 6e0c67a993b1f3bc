"""turtlesim's message and service types, in .msg syntax (the course starts with turtlesim).

Kept apart from the other extra types so that each package's block is its own; ``_types``
merges these dicts into its own.
"""

from __future__ import annotations

from typing import Final

__all__ = ["TURTLESIM_MESSAGES", "TURTLESIM_SERVICES"]

TURTLESIM_MESSAGES: Final = {
    "turtlesim/msg/Pose": (
        "float32 x\nfloat32 y\nfloat32 theta\n\nfloat32 linear_velocity\nfloat32 angular_velocity"
    ),
    "turtlesim/msg/Color": "uint8 r\nuint8 g\nuint8 b",
}
TURTLESIM_SERVICES: Final = {
    "turtlesim/srv/Spawn": ("float32 x\nfloat32 y\nfloat32 theta\nstring name", "string name"),
    "turtlesim/srv/Kill": ("string name", ""),
    "turtlesim/srv/SetPen": ("uint8 r\nuint8 g\nuint8 b\nuint8 width\nuint8 off", ""),
    "turtlesim/srv/TeleportAbsolute": ("float32 x\nfloat32 y\nfloat32 theta", ""),
    "turtlesim/srv/TeleportRelative": ("float32 linear\nfloat32 angular", ""),
}
