"""actionlib.exceptions as ROS 1 has it, from belvedere's actionlib."""

from belvedere.ros1.actionlib import (
    ActionException,
)

__all__ = [
    "ActionException",
]
