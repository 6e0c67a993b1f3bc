"""move_base's own parameters (each planner, costmap and recovery reads its own)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

__all__ = ["MoveBaseParams"]


@dataclass(frozen=True)
class MoveBaseParams:
    """move_base's own parameters, with its defaults."""

    base_global_planner: str = "navfn/NavfnROS"
    base_local_planner: str = "base_local_planner/TrajectoryPlannerROS"
    controller_frequency: float = 20.0
    planner_frequency: float = 0.0
    planner_patience: float = 5.0
    controller_patience: float = 15.0
    max_planning_retries: int = -1
    oscillation_timeout: float = 0.0
    oscillation_distance: float = 0.5
    recovery_behavior_enabled: bool = True
    clearing_rotation_allowed: bool = True
    shutdown_costmaps: bool = False
    conservative_reset_dist: float = 3.0

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> MoveBaseParams:
        fields: dict[str, Any] = {}
        for name, default in cls().__dict__.items():
            if name not in values:
                continue
            value = values[name]
            if isinstance(default, bool):
                if not isinstance(value, bool):
                    message = f"parameter {name} must be true or false, got {value!r}"
                    raise ValueError(message)
            elif isinstance(default, int | float):
                if isinstance(value, bool) or not isinstance(value, int | float):
                    message = f"parameter {name} must be a number, got {value!r}"
                    raise ValueError(message)
                value = type(default)(value)
            else:
                value = str(value)
            fields[name] = value
        params = cls(**fields)
        if params.controller_frequency <= 0:
            message = "parameter controller_frequency must be positive"
            raise ValueError(message)
        return params
