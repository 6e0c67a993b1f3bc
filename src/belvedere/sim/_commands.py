"""Commands beyond physical sense are refused, with one warning per burst.

A robot's command topics (``cmd_vel``, a joint's ``command``) take any float a publisher
sends. A value that is not finite, or a speed no ground robot is ever commanded, only breaks
the simulation: the kinematic base's pose overflows, and MuJoCo resets a body it cannot
integrate to the origin mid-run. Such a command is ignored (the last good one stays), with one
warning for the first of a burst and a count when sane commands resume.

The bounds are parameters, so a launch file or ``belvedere sim --max-speed`` can change them:

``/belvedere/max_speed`` (m/s, default 350)
    for linear velocities. Above the land speed record (341 m/s): no ground robot is
    commanded faster, and at 1 kHz a body then moves 0.35 m per physics step already.
``/belvedere/max_turn_rate`` (rad/s, default 350)
    for angular velocities: about 56 turns a second, beyond any base or wheel command.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from typing import Final

from belvedere.errors import BelvedereError
from belvedere.graph import Graph

__all__ = [
    "DEFAULT_MAX_SPEED",
    "DEFAULT_MAX_TURN_RATE",
    "MAX_SPEED_PARAM",
    "MAX_TURN_RATE_PARAM",
    "CommandGate",
]

MAX_SPEED_PARAM: Final = "/belvedere/max_speed"
MAX_TURN_RATE_PARAM: Final = "/belvedere/max_turn_rate"
DEFAULT_MAX_SPEED: Final = 350.0
DEFAULT_MAX_TURN_RATE: Final = 350.0

_NO_VALUES: Final[Mapping[str, float]] = {}


class CommandGate:
    """Decides, for one command subscriber, whether each command is sensible."""

    def __init__(self, owner: str, graph: Graph, logger: logging.Logger) -> None:
        self.owner = owner
        self.logger = logger
        self.max_speed = _bound(graph, MAX_SPEED_PARAM, DEFAULT_MAX_SPEED, "m/s")
        self.max_turn_rate = _bound(graph, MAX_TURN_RATE_PARAM, DEFAULT_MAX_TURN_RATE, "rad/s")
        self.refused = 0
        """Commands refused since the last accepted one."""

    def accept(
        self,
        *,
        linear: Mapping[str, float] = _NO_VALUES,
        angular: Mapping[str, float] = _NO_VALUES,
        other: Mapping[str, float] = _NO_VALUES,
    ) -> bool:
        """True for a command to obey: every value finite, velocities within the bounds.
        ``linear`` and ``angular`` are velocities by name (``linear.x``), ``other`` anything
        only required to be finite (a joint position or effort)."""
        problems = [f"{k}={v!r} (not finite)" for k, v in other.items() if not math.isfinite(v)]
        for values, bound, unit, param in (
            (linear, self.max_speed, "m/s", MAX_SPEED_PARAM),
            (angular, self.max_turn_rate, "rad/s", MAX_TURN_RATE_PARAM),
        ):
            for name, value in values.items():
                if not math.isfinite(value):
                    problems.append(f"{name}={value!r} (not finite)")
                elif abs(value) > bound:
                    problems.append(f"{name}={value:g} (beyond ±{bound:g} {unit}, {param})")
        if not problems:
            if self.refused > 1:
                self.logger.warning("%s: %d commands were ignored", self.owner, self.refused)
            self.refused = 0
            return True
        self.refused += 1
        if self.refused == 1:  # one line per burst, not a flood
            self.logger.warning(
                "%s: ignored a command with %s; keeping the last one",
                self.owner,
                ", ".join(problems),
            )
        return False


def _bound(graph: Graph, name: str, default: float, unit: str) -> float:
    value = graph.params.get(name, default)
    if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
        msg = f"parameter {name} must be a positive number of {unit}, got {value!r}"
        raise BelvedereError(msg)
    return float(value)
