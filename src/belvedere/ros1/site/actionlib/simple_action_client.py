"""actionlib.simple_action_client as ROS 1 has it, from belvedere's actionlib."""

from belvedere.ros1.actionlib import (
    ActionClient,
    CommState,
    GoalStatus,
    SimpleActionClient,
    SimpleGoalState,
    get_name_of_constant,
)

__all__ = [
    "ActionClient",
    "CommState",
    "GoalStatus",
    "SimpleActionClient",
    "SimpleGoalState",
    "get_name_of_constant",
]
