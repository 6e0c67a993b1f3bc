"""actionlib.server_goal_handle as ROS 1 has it, from belvedere's actionlib."""

from belvedere.ros1.actionlib import (
    ServerGoalHandle,
)

__all__ = [
    "ServerGoalHandle",
]
