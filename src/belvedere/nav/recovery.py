"""move_base's recovery behaviours over plain arrays: the ``recovery_behaviors`` list,
clear_costmap_recovery's parameters and rotate_recovery's decisions.

rotate_recovery's decisions: move_base drives the turn, this says which
way and how fast, and when the turn is done or blocked.

rotate_recovery/RotateRecovery turns the robot once around in place (to let the sensors clear
the costmaps): each cycle at ``frequency`` it checks that the rest of the turn (half a turn
plus the way to the opposite heading, then the way back to the start) is free for the
footprint on the local costmap every ``sim_granularity`` radians, and commands
``sqrt(2·acc_lim_th·left)`` within ``[min_in_place_vel_theta, max_vel_theta]``; it ends once
it passed the opposite heading and came back within ``yaw_goal_tolerance`` of the start, and
aborts the moment a pose of the rest of the turn would collide.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum
from typing import Any, Final

import numpy as np
import numpy.typing as npt

from belvedere.nav._params import ParamReader
from belvedere.nav.costmap import CostGrid
from belvedere.nav.local import FootprintModel

__all__ = [
    "RECOVERY_TYPES",
    "ClearCostmapParams",
    "RecoveryBehavior",
    "RecoveryListError",
    "RotateOutcome",
    "RotateRecovery",
    "RotateRecoveryParams",
    "RotateStep",
    "first_collision",
    "recovery_behaviors",
]

Floats = npt.NDArray[np.float64]

CLEAR_COSTMAP: Final = "clear_costmap_recovery/ClearCostmapRecovery"
ROTATE: Final = "rotate_recovery/RotateRecovery"
RECOVERY_TYPES: Final = (CLEAR_COSTMAP, ROTATE)
"""The recovery behaviour plugins belvedere's move_base runs."""


class RecoveryListError(ValueError):
    """A bad ``recovery_behaviors`` list; ``keys`` lead from the list to the bad value
    (entry index, then ``name`` or ``type``) so the caller can say its line."""

    def __init__(self, message: str, *keys: str | int) -> None:
        super().__init__(message)
        self.keys = keys


@dataclass(frozen=True)
class RecoveryBehavior:
    """One entry of move_base's ``recovery_behaviors``: its parameters live in ``~<name>/``."""

    name: str
    type: str
    """A full plugin name, one of :data:`RECOVERY_TYPES`."""


def _plugin_type(kind: str, index: int) -> str:
    if kind in RECOVERY_TYPES:
        return kind
    # pluginlib accepts a bare class name when one declared class has it, as move_base does
    matches = [full for full in RECOVERY_TYPES if full.rsplit("/", 1)[-1] == kind]
    if len(matches) == 1:
        return matches[0]
    message = (
        f"recovery_behaviors[{index}]: unknown recovery behavior type {kind!r} "
        f"(supported: {', '.join(RECOVERY_TYPES)})"
    )
    raise RecoveryListError(message, index, "type")


def recovery_behaviors(value: Any) -> tuple[RecoveryBehavior, ...]:
    """move_base's ``recovery_behaviors`` parameter: a list of ``{name, type}`` maps with
    distinct names and supported types (where ROS logs an error and falls back to its default
    list, this is one error).

    Raises:
        RecoveryListError: naming the bad entry and what was expected."""
    if not isinstance(value, list):
        message = (
            "recovery_behaviors must be a list of {name: ..., type: ...} maps, "
            f"got {type(value).__name__} {value!r}"
        )
        raise RecoveryListError(message)
    out: list[RecoveryBehavior] = []
    for index, entry in enumerate(value):
        if not isinstance(entry, dict):
            message = (
                f"recovery_behaviors[{index}] must be a map with a name and a type, got {entry!r}"
            )
            raise RecoveryListError(message, index)
        for key in ("name", "type"):
            if not isinstance(entry.get(key), str) or not entry[key]:
                message = (
                    f"recovery_behaviors[{index}] needs a {key} (a string), got {entry.get(key)!r}"
                )
                raise RecoveryListError(message, index, key if key in entry else "")
        name = str(entry["name"])
        if any(b.name == name for b in out):
            message = f"recovery_behaviors[{index}]: the name {name!r} is used twice"
            raise RecoveryListError(message, index, "name")
        out.append(RecoveryBehavior(name, _plugin_type(str(entry["type"]), index)))
    return tuple(out)


@dataclass(frozen=True)
class ClearCostmapParams:
    """clear_costmap_recovery/ClearCostmapRecovery's parameters (``~<name>/``): the layers it
    resets (by the part of their name after the last ``/``; the default ``obstacles`` matches
    no layer of a costmap in the pre-Hydro style, whose layer is ``obstacle_layer``), outside
    or inside (``invert_area_to_clear``) a square of side ``reset_distance`` at the robot, on
    the ``local``, ``global`` or ``both`` costmaps, updating them at once with
    ``force_updating``."""

    reset_distance: float = 3.0
    layer_names: tuple[str, ...] = ("obstacles",)
    invert_area_to_clear: bool = False
    force_updating: bool = False
    affected_maps: str = "both"

    @classmethod
    def from_mapping(
        cls, name: str, own: Mapping[str, Any], reset_distance: float | None = None
    ) -> ClearCostmapParams:
        """From the recovery's namespace ``name``; ``reset_distance`` is the one move_base
        sets there for its default recoveries (over any value given), else the namespace's
        own (3 m by default)."""
        if reset_distance is None:
            reset_distance = ParamReader(own).number(3.0, "reset_distance")
            if reset_distance < 0:
                message = f"parameter {name}/reset_distance must not be negative"
                raise ValueError(message)
        layers = own.get("layer_names", ["obstacles"])
        if not isinstance(layers, list) or not all(isinstance(n, str) for n in layers):
            message = f"parameter {name}/layer_names must be a list of layer names, got {layers!r}"
            raise ValueError(message)
        maps = own.get("affected_maps", "both")
        if maps not in ("local", "global", "both"):
            message = (
                f"parameter {name}/affected_maps must be 'local', 'global' or 'both', got {maps!r}"
            )
            raise ValueError(message)
        flags = []
        for key in ("invert_area_to_clear", "force_updating"):
            value = own.get(key, False)
            if not isinstance(value, bool):
                message = f"parameter {name}/{key} must be true or false, got {value!r}"
                raise ValueError(message)
            flags.append(value)
        invert, force = flags
        return cls(reset_distance, tuple(layers), invert, force, str(maps))

    def affects(self, which: str) -> bool:
        """Whether the ``local`` or ``global`` costmap is cleared."""
        return self.affected_maps in (which, "both")


@dataclass(frozen=True)
class RotateRecoveryParams:
    """RotateRecovery's parameters: its own (``~<name>/sim_granularity``, ``frequency``) and
    those it reads from ``~TrajectoryPlannerROS/`` (old names as well)."""

    sim_granularity: float = 0.017
    """Radians between the poses checked (a degree)."""
    frequency: float = 20.0
    """Hz of the turn's control loop."""
    acc_lim_th: float = 3.2
    max_rotational_vel: float = 1.0
    min_rotational_vel: float = 0.4
    tolerance: float = 0.10

    @classmethod
    def from_mapping(
        cls, own: Mapping[str, Any], local_planner: Mapping[str, Any] | None = None
    ) -> RotateRecoveryParams:
        """From the recovery's namespace and the ``TrajectoryPlannerROS`` namespace (as
        rotate_recovery reads it whatever the local planner is)."""
        read = ParamReader(own)
        blp = ParamReader(local_planner or {})
        params = cls(
            sim_granularity=read.number(0.017, "sim_granularity"),
            frequency=read.number(20.0, "frequency"),
            acc_lim_th=blp.number(3.2, "acc_lim_theta", "acc_lim_th"),
            max_rotational_vel=blp.number(1.0, "max_vel_theta", "max_rotational_vel"),
            min_rotational_vel=blp.number(
                0.4, "min_in_place_vel_theta", "min_in_place_rotational_vel"
            ),
            tolerance=blp.number(0.10, "yaw_goal_tolerance"),
        )
        for name in ("sim_granularity", "frequency"):
            if getattr(params, name) <= 0:
                message = f"parameter {name} must be positive, got {getattr(params, name):g}"
                raise ValueError(message)
        return params

    @property
    def period(self) -> float:
        return 1.0 / self.frequency


def first_collision(
    grid: CostGrid,
    pose: tuple[float, float, float],
    footprint: Floats,
    sweep: float,
    granularity: float,
) -> float | None:
    """The first angle (radians turned counter-clockwise from the pose, a multiple of
    ``granularity`` below ``sweep``) at which the footprint would collide on the grid, or
    None when the whole sweep is free."""
    if sweep <= 0:
        return None
    angles = np.arange(0.0, sweep, granularity)
    model = FootprintModel(np.asarray(footprint, dtype=np.float64), grid.resolution)
    x = np.full(len(angles), pose[0])
    y = np.full(len(angles), pose[1])
    _, valid = model.cost(grid, x, y, pose[2] + angles)
    if valid.all():
        return None
    return float(angles[int(np.argmin(valid))])


class RotateOutcome(Enum):
    ROTATING = "rotating"
    DONE = "done"
    BLOCKED = "blocked"


@dataclass(frozen=True)
class RotateStep:
    """One cycle's decision: turn at ``vth`` (rad/s, counter-clockwise) while ROTATING."""

    outcome: RotateOutcome
    vth: float = 0.0
    left: float = 0.0
    """Radians of the turn still to go."""
    blocked_at: float | None = None
    """With BLOCKED: how far ahead (radians) the footprint would collide."""


class RotateRecovery:
    """One in-place turn, cycle by cycle: call :meth:`step` with the current pose every
    ``params.period`` seconds and send its ``vth`` until it says DONE or BLOCKED (then send a
    stop)."""

    def __init__(self, params: RotateRecoveryParams, start_yaw: float) -> None:
        self.params = params
        self.start_yaw = start_yaw
        self.got_180 = False

    def step(
        self, grid: CostGrid, pose: tuple[float, float, float], footprint: Floats
    ) -> RotateStep:
        p = self.params
        yaw = pose[2]
        back = abs(math.remainder(self.start_yaw - yaw, math.tau))
        if self.got_180 and back <= p.tolerance:
            return RotateStep(RotateOutcome.DONE)
        if not self.got_180:
            to_180 = abs(math.remainder(self.start_yaw + math.pi - yaw, math.tau))
            left = math.pi + to_180
            if to_180 < p.tolerance:
                self.got_180 = True
        else:
            left = back
        hit = first_collision(grid, pose, footprint, left, p.sim_granularity)
        if hit is not None:
            return RotateStep(RotateOutcome.BLOCKED, left=left, blocked_at=hit)
        vth = math.sqrt(2 * p.acc_lim_th * left)
        vth = min(max(vth, p.min_rotational_vel), p.max_rotational_vel)
        return RotateStep(RotateOutcome.ROTATING, vth=vth, left=left)
