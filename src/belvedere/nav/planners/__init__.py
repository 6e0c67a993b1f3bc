"""move_base's global planners over a :class:`~belvedere.nav.costmap.CostGrid`."""

from belvedere.nav._plugins import UnknownPluginError
from belvedere.nav.planners._orientation import OrientationMode
from belvedere.nav.planners._planners import (
    PLUGINS,
    GlobalPlanner,
    GlobalPlannerParams,
    GlobalPlannerPlugin,
    NavfnParams,
    NavfnPlanner,
    NoPathError,
    make_global_planner,
)
from belvedere.nav.planners._wavefront import POT_HIGH

__all__ = [
    "PLUGINS",
    "POT_HIGH",
    "GlobalPlanner",
    "GlobalPlannerParams",
    "GlobalPlannerPlugin",
    "NavfnParams",
    "NavfnPlanner",
    "NoPathError",
    "OrientationMode",
    "UnknownPluginError",
    "make_global_planner",
]
