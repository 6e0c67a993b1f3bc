"""actionlib.action_client as ROS 1 has it, from belvedere's actionlib."""

from belvedere.ros1.actionlib import (
    ActionClient,
    ClientGoalHandle,
    CommState,
    CommStateMachine,
    GoalID,
    GoalManager,
    GoalStatus,
    GoalStatusArray,
    TerminalState,
    get_name_of_constant,
)

__all__ = [
    "ActionClient",
    "ClientGoalHandle",
    "CommState",
    "CommStateMachine",
    "GoalID",
    "GoalManager",
    "GoalStatus",
    "GoalStatusArray",
    "TerminalState",
    "get_name_of_constant",
]
