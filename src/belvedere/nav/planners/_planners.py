"""The global planners move_base loads: ``navfn/NavfnROS`` and ``global_planner/GlobalPlanner``.

Both spread a potential from the robot's cell over the costmap and walk down it from the goal.
They differ as in ROS:

navfn
    costs ``50 + 3·cost`` (unknown as 253 with ``allow_unknown``), a 7-cell frame of the map
    never entered, the quadratic update, gradient descent, path points at cell corners, and
    ``default_tolerance``: the reachable point nearest the goal within a square of that half
    width (stepping by the resolution) when the goal itself is not reachable.
global_planner
    ``neutral_cost + cost_factor·cost`` capped below ``lethal_cost``, Dijkstra or A*
    (``use_dijkstra``), quadratic or plain sums (``use_quadratic``), gradient or grid paths
    (``use_grid_path``), points at cell centres, ``orientation_mode``. Like ROS Noetic it reads
    ``default_tolerance`` but does not use it (ros-planning/navigation#262). Its A* is
    ``AStarExpansion`` (see ``_astar``), with the quadratic potential too. Unless
    ``old_navfn_behavior``, the cells within two of the goal that the search did not reach get
    a potential from their neighbours before the path is walked (``clearEndpoint``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Final, Protocol

import numpy as np
import numpy.typing as npt

from belvedere.nav._plugins import UnknownPluginError
from belvedere.nav.costmap import FREE, NO_INFORMATION, CostGrid
from belvedere.nav.planners._astar import astar, clear_endpoint
from belvedere.nav.planners._orientation import OrientationMode, orient
from belvedere.nav.planners._paths import gradient_path, grid_path
from belvedere.nav.planners._wavefront import POT_HIGH, Field, propagate

__all__ = [
    "PLUGINS",
    "GlobalPlanner",
    "GlobalPlannerParams",
    "GlobalPlannerPlugin",
    "NavfnParams",
    "NavfnPlanner",
    "NoPathError",
    "make_global_planner",
]

Path = npt.NDArray[np.float64]

_NAVFN_NEUTRAL: Final = 50.0
_NAVFN_FACTOR: Final = 3.0
_NAVFN_OBSTACLE: Final = 254.0
_NAVFN_BORDER: Final = 7


class NoPathError(ValueError):
    """The planner found no path (off the map, an unreachable goal)."""


class GlobalPlanner(Protocol):
    """What move_base asks of a global planner."""

    def plan(self, grid: CostGrid, start: npt.ArrayLike, goal: npt.ArrayLike) -> Path:
        """Poses (N, 3) from ``start`` to ``goal`` (x, y, yaw) in the grid's frame.

        Raises:
            NoPathError: no path.
        """
        ...


def _number(params: Mapping[str, Any], name: str, default: float) -> float:
    value = params.get(name, default)
    if isinstance(value, bool) or not isinstance(value, int | float):
        message = f"parameter {name!r} must be a number, not {value!r}"
        raise ValueError(message)
    return float(value)


def _flag(params: Mapping[str, Any], name: str, default: bool) -> bool:
    value = params.get(name, default)
    if not isinstance(value, bool):
        message = f"parameter {name!r} must be true or false, not {value!r}"
        raise ValueError(message)
    return value


def _integer(params: Mapping[str, Any], name: str, default: int) -> int:
    value = params.get(name, default)
    if isinstance(value, bool) or not isinstance(value, int):
        message = f"parameter {name!r} must be an integer, not {value!r}"
        raise ValueError(message)
    return value


@dataclass(frozen=True)
class NavfnParams:
    allow_unknown: bool = True
    default_tolerance: float = 0.0
    visualize_potential: bool = False

    @classmethod
    def from_mapping(cls, params: Mapping[str, Any]) -> NavfnParams:
        tolerance = _number(params, "default_tolerance", 0.0)
        if tolerance < 0:
            message = f"parameter 'default_tolerance' must not be negative, not {tolerance}"
            raise ValueError(message)
        return cls(
            allow_unknown=_flag(params, "allow_unknown", True),
            default_tolerance=tolerance,
            visualize_potential=_flag(params, "visualize_potential", False),
        )


@dataclass(frozen=True)
class GlobalPlannerParams:
    allow_unknown: bool = True
    default_tolerance: float = 0.0
    use_dijkstra: bool = True
    use_quadratic: bool = True
    use_grid_path: bool = False
    old_navfn_behavior: bool = False
    lethal_cost: int = 253
    neutral_cost: int = 50
    cost_factor: float = 3.0
    orientation_mode: OrientationMode = OrientationMode.NONE
    orientation_window_size: int = 1
    outline_map: bool = True
    visualize_potential: bool = False

    @classmethod
    def from_mapping(cls, params: Mapping[str, Any]) -> GlobalPlannerParams:
        mode = _integer(params, "orientation_mode", 0)
        if mode not in {m.value for m in OrientationMode}:
            message = f"parameter 'orientation_mode' must be 0 to 6, not {mode}"
            raise ValueError(message)
        lethal = _integer(params, "lethal_cost", 253)
        neutral = _integer(params, "neutral_cost", 50)
        if not 1 <= lethal <= 255 or not 1 <= neutral < lethal:
            message = (
                f"parameters 'lethal_cost' ({lethal}) and 'neutral_cost' ({neutral}) must "
                "satisfy 1 <= neutral_cost < lethal_cost <= 255"
            )
            raise ValueError(message)
        window = _integer(params, "orientation_window_size", 1)
        if window < 1:
            message = f"parameter 'orientation_window_size' must be at least 1, not {window}"
            raise ValueError(message)
        return cls(
            allow_unknown=_flag(params, "allow_unknown", True),
            default_tolerance=_number(params, "default_tolerance", 0.0),
            use_dijkstra=_flag(params, "use_dijkstra", True),
            use_quadratic=_flag(params, "use_quadratic", True),
            use_grid_path=_flag(params, "use_grid_path", False),
            old_navfn_behavior=_flag(params, "old_navfn_behavior", False),
            lethal_cost=lethal,
            neutral_cost=neutral,
            cost_factor=_number(params, "cost_factor", 3.0),
            orientation_mode=OrientationMode(mode),
            orientation_window_size=window,
            outline_map=_flag(params, "outline_map", True),
            visualize_potential=_flag(params, "visualize_potential", False),
        )


def _pose(value: npt.ArrayLike, what: str) -> npt.NDArray[np.float64]:
    pose = np.asarray(value, dtype=np.float64).reshape(-1)
    if pose.shape != (3,) or not np.isfinite(pose).all():
        message = f"the {what} must be a finite (x, y, yaw), not {value!r}"
        raise ValueError(message)
    return pose


def _cells(
    grid: CostGrid, start: npt.NDArray[np.float64], goal: npt.NDArray[np.float64]
) -> tuple[tuple[int, int], tuple[int, int]]:
    start_cell = grid.world_to_map(start[0], start[1])
    if start_cell is None:
        message = (
            f"the robot's start position ({start[0]:.2f}, {start[1]:.2f}) is off the global costmap"
        )
        raise NoPathError(message)
    goal_cell = grid.world_to_map(goal[0], goal[1])
    if goal_cell is None:
        message = (
            f"the goal sent to the planner ({goal[0]:.2f}, {goal[1]:.2f}) is off the global costmap"
        )
        raise NoPathError(message)
    return start_cell, goal_cell


def _no_path(start: npt.NDArray[np.float64], goal: npt.NDArray[np.float64]) -> NoPathError:
    message = f"no path from ({start[0]:.2f}, {start[1]:.2f}) to ({goal[0]:.2f}, {goal[1]:.2f})"
    return NoPathError(message)


def _finish(
    cells: npt.NDArray[np.float64], grid: CostGrid, offset: float, goal: npt.NDArray[np.float64]
) -> Path:
    """Cell coordinates walked from the goal → world poses from the robot, goal appended."""
    ordered = cells[::-1]
    path = np.zeros((len(ordered) + 1, 3))
    path[:-1, 0] = grid.origin_x + (ordered[:, 0] + offset) * grid.resolution
    path[:-1, 1] = grid.origin_y + (ordered[:, 1] + offset) * grid.resolution
    path[-1] = goal
    return path


class NavfnPlanner:
    """``navfn/NavfnROS``."""

    def __init__(self, params: NavfnParams) -> None:
        self.params = params
        self.potential: Field | None = None

    def costs(self, costs: npt.NDArray[np.uint8]) -> tuple[Field, npt.NDArray[np.bool_]]:
        """navfn's translation of costmap costs: step costs and where the wave may go."""
        raw = costs.astype(np.float32)
        step = np.minimum(_NAVFN_NEUTRAL + _NAVFN_FACTOR * raw, _NAVFN_OBSTACLE - 1)
        passable = costs < 253
        if self.params.allow_unknown:
            unknown = costs == NO_INFORMATION
            step[unknown] = _NAVFN_OBSTACLE - 1
            passable |= unknown
        border = np.ones_like(passable)
        b = _NAVFN_BORDER
        border[b : costs.shape[0] - b, b : costs.shape[1] - b] = False
        passable &= ~border
        return step.astype(np.float32), passable

    def plan(self, grid: CostGrid, start: npt.ArrayLike, goal: npt.ArrayLike) -> Path:
        start_pose, goal_pose = _pose(start, "start"), _pose(goal, "goal")
        start_cell, goal_cell = _cells(grid, start_pose, goal_pose)
        costs = grid.costs.copy()
        costs[start_cell[1], start_cell[0]] = FREE  # navfn clears the robot's cell
        step, passable = self.costs(costs)
        tolerance = self.params.default_tolerance
        pot = propagate(
            step,
            passable,
            start_cell,
            target=goal_cell if tolerance == 0 else None,
            increment=2 * _NAVFN_NEUTRAL,
            quadratic=True,
        )
        self.potential = pot
        best = self._reachable_goal(grid, pot, goal_pose, tolerance)
        if best is None:
            raise _no_path(start_pose, goal_pose)
        cell = grid.world_to_map(best[0], best[1])
        assert cell is not None  # the search only keeps points on the map
        walked = gradient_path(
            pot, cell, stop_below=_NAVFN_NEUTRAL, max_steps=grid.width * grid.height // 2
        )
        if walked is None:
            raise _no_path(start_pose, goal_pose)
        return _finish(walked, grid, 0.0, best)

    @staticmethod
    def _reachable_goal(
        grid: CostGrid, pot: Field, goal: npt.NDArray[np.float64], tolerance: float
    ) -> npt.NDArray[np.float64] | None:
        """navfn's goal search: the reached point closest to the goal on a resolution-spaced
        square of half width ``tolerance`` (just the goal with no tolerance)."""
        best: npt.NDArray[np.float64] | None = None
        best_sq = math.inf
        res = grid.resolution
        y = goal[1] - tolerance
        while y <= goal[1] + tolerance:
            x = goal[0] - tolerance
            while x <= goal[0] + tolerance:
                cell = grid.world_to_map(x, y)
                sq = (x - goal[0]) ** 2 + (y - goal[1]) ** 2
                if cell is not None and pot[cell[1], cell[0]] < POT_HIGH and sq < best_sq:
                    best_sq = sq
                    best = np.array([x, y, goal[2]])
                x += res
            y += res
        return best


class GlobalPlannerPlugin:
    """``global_planner/GlobalPlanner``."""

    def __init__(self, params: GlobalPlannerParams) -> None:
        self.params = params
        self.potential: Field | None = None

    def costs(self, costs: npt.NDArray[np.uint8]) -> tuple[Field, npt.NDArray[np.bool_]]:
        """global_planner's step costs (``neutral + factor·cost``, below ``lethal_cost``) and
        where the wave may go."""
        p = self.params
        raw = costs.astype(np.float32)
        step = np.minimum(raw * p.cost_factor + p.neutral_cost, p.lethal_cost - 1)
        passable = costs < p.lethal_cost - 1
        if p.allow_unknown:
            passable |= costs == NO_INFORMATION
        return step.astype(np.float32), passable

    def _astar_passable(self, costs: npt.NDArray[np.uint8]) -> npt.NDArray[np.bool_]:
        """Where ``AStarExpansion`` goes: below ``lethal_cost`` (one higher than Dijkstra's
        limit), or unknown with ``allow_unknown``."""
        passable = costs < self.params.lethal_cost
        if self.params.allow_unknown:
            passable |= costs == NO_INFORMATION
        return passable

    def plan(self, grid: CostGrid, start: npt.ArrayLike, goal: npt.ArrayLike) -> Path:
        p = self.params
        start_pose, goal_pose = _pose(start, "start"), _pose(goal, "goal")
        start_cell, goal_cell = _cells(grid, start_pose, goal_pose)
        costs = grid.costs.copy()
        costs[start_cell[1], start_cell[0]] = FREE
        step, passable = self.costs(costs)
        if p.use_dijkstra:
            pot = propagate(
                step,
                passable,
                start_cell,
                target=goal_cell,
                increment=2 * p.neutral_cost,
                quadratic=p.use_quadratic,
            )
        else:
            reached = astar(
                costs,
                self._astar_passable(costs),
                start_cell,
                goal_cell,
                neutral=p.neutral_cost,
                quadratic=p.use_quadratic,
            )
            if reached is None:
                raise _no_path(start_pose, goal_pose)
            pot = reached
        if not p.old_navfn_behavior:
            clear_endpoint(costs, pot, goal_cell, neutral=p.neutral_cost, quadratic=p.use_quadratic)
        self.potential = pot
        if pot[goal_cell[1], goal_cell[0]] >= POT_HIGH:
            raise _no_path(start_pose, goal_pose)
        limit = grid.width * grid.height * 4
        if p.use_grid_path:
            walked = grid_path(pot, goal_cell, max_steps=limit)
        else:
            walked = gradient_path(pot, goal_cell, stop_below=p.neutral_cost, max_steps=limit)
        if walked is None:
            raise _no_path(start_pose, goal_pose)
        offset = 0.0 if p.old_navfn_behavior else 0.5
        path = _finish(walked, grid, offset, goal_pose)
        orient(path, float(start_pose[2]), p.orientation_mode, p.orientation_window_size)
        return path


PLUGINS: Final = ("navfn/NavfnROS", "global_planner/GlobalPlanner")


def make_global_planner(plugin: str, params: Mapping[str, Any]) -> GlobalPlanner:
    """The planner move_base's ``base_global_planner`` names, with its ``~<Name>/`` parameters.

    Raises:
        UnknownPluginError: not a supported planner (the message lists them).
        ValueError: a parameter of the wrong type or range (the message names it).
    """
    if plugin == "navfn/NavfnROS":
        return NavfnPlanner(NavfnParams.from_mapping(params))
    if plugin == "global_planner/GlobalPlanner":
        return GlobalPlannerPlugin(GlobalPlannerParams.from_mapping(params))
    kind = "global planner"
    raise UnknownPluginError(kind, plugin, PLUGINS)
