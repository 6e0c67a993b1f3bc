"""actionlib.goal_id_generator as ROS 1 has it, from belvedere's actionlib."""

from belvedere.ros1.actionlib import (
    GoalIDGenerator,
)

__all__ = [
    "GoalIDGenerator",
]
