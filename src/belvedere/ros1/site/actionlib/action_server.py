"""actionlib.action_server as ROS 1 has it, from belvedere's actionlib."""

from belvedere.ros1.actionlib import (
    ActionException,
    ActionServer,
    GoalID,
    GoalIDGenerator,
    GoalStatus,
    GoalStatusArray,
    ServerGoalHandle,
    StatusTracker,
    nop_cb,
)

__all__ = [
    "ActionException",
    "ActionServer",
    "GoalID",
    "GoalIDGenerator",
    "GoalStatus",
    "GoalStatusArray",
    "ServerGoalHandle",
    "StatusTracker",
    "nop_cb",
]
