"""move_base's local planners over plain arrays: ``base_local_planner/TrajectoryPlannerROS``
and ``dwa_local_planner/DWAPlannerROS``, reading a :class:`~belvedere.nav.costmap.CostGrid`.

Example::

    planner = make_local_planner("dwa_local_planner/DWAPlannerROS", {"max_vel_x": 0.3})
    planner.set_plan(path)                      # (N, 3) poses in the grid's frame
    command = planner.compute(grid, pose, velocity, footprint)
    if planner.goal_reached(pose, velocity): ...

The plan, the pose and the grid share one frame (the local costmap's global frame: the
caller transforms the global plan into it, as the ROS planners do with tf). Each
``compute`` is one ``computeVelocityCommands``: it cuts the plan to the grid (and prunes the
poses left behind, with ``prune_plan``), lays the path and goal distance maps over the grid,
rolls out every velocity sample at once and picks the cheapest valid one.

Where belvedere differs from the C++ planners:

- The footprint's outline is sampled a cell apart along its edges rather than rasterised
  with Bresenham's line, so a cell where two edges meet may be looked at by one and not the
  other. A footprint of fewer than three points is a circle, checked at its centre cell.
- While TrajectoryPlannerROS stops and turns at the goal it recomputes its distance maps
  (for the collision checks) but not a full set of rollouts, whose result ROS throws away
  there; so its anti-oscillation flags do not change during that phase.
- ``y_vels`` may be a YAML list as well as ROS's string form.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from belvedere.nav._plugins import UnknownPluginError
from belvedere.nav.local._base import Command, LocalPlanner, NoTrajectoryError
from belvedere.nav.local._dwa import DWAPlannerROS
from belvedere.nav.local._maps import FootprintModel
from belvedere.nav.local._params import DWAPlannerParams, TrajectoryPlannerParams
from belvedere.nav.local._trajectory import TrajectoryPlannerROS

__all__ = [
    "LOCAL_PLANNERS",
    "Command",
    "DWAPlannerParams",
    "DWAPlannerROS",
    "FootprintModel",
    "LocalPlanner",
    "NoTrajectoryError",
    "TrajectoryPlannerParams",
    "TrajectoryPlannerROS",
    "UnknownPluginError",
    "make_local_planner",
]

LOCAL_PLANNERS = (TrajectoryPlannerROS.name, DWAPlannerROS.name)
"""The ``base_local_planner`` values move_base accepts."""


def make_local_planner(plugin: str, params: Mapping[str, Any]) -> LocalPlanner:
    """The local planner a ``base_local_planner`` value names, with the parameters of its
    namespace (``~<TrajectoryPlannerROS|DWAPlannerROS>/``, plus ``controller_frequency``).

    Raises:
        UnknownPluginError: for a name not in :data:`LOCAL_PLANNERS`.
        ValueError: for a parameter of the wrong type or an unusable value (naming it).
    """
    if plugin == TrajectoryPlannerROS.name:
        return TrajectoryPlannerROS(TrajectoryPlannerParams.from_mapping(params))
    if plugin == DWAPlannerROS.name:
        return DWAPlannerROS(DWAPlannerParams.from_mapping(params))
    kind = "local planner"
    raise UnknownPluginError(kind, plugin, LOCAL_PLANNERS)
