"""actionlib.simple_action_server as ROS 1 has it, from belvedere's actionlib."""

from belvedere.ros1.actionlib import (
    ActionServer,
    GoalStatus,
    ServerGoalHandle,
    SimpleActionServer,
    nop_cb,
)

__all__ = [
    "ActionServer",
    "GoalStatus",
    "ServerGoalHandle",
    "SimpleActionServer",
    "nop_cb",
]
