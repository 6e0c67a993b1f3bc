"""Simulation engines: the kinematic (ArbotiX-style) engine and the MuJoCo physics engine.

Both take the same robot model and speak the same topics (``/odom``, ``/tf``,
``/joint_states``); the kinematic one moves the robot exactly as commanded, with no physics.
Both refuse commands beyond physical sense the same way (:class:`CommandGate`).
"""

from belvedere.sim._commands import (
    DEFAULT_MAX_SPEED,
    DEFAULT_MAX_TURN_RATE,
    MAX_SPEED_PARAM,
    MAX_TURN_RATE_PARAM,
    CommandGate,
)
from belvedere.sim._services import SAVE_WORLD, SAVE_WORLD_TYPE

__all__ = [
    "DEFAULT_MAX_SPEED",
    "DEFAULT_MAX_TURN_RATE",
    "MAX_SPEED_PARAM",
    "MAX_TURN_RATE_PARAM",
    "SAVE_WORLD",
    "SAVE_WORLD_TYPE",
    "CommandGate",
]
