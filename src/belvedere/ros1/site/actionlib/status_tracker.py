"""actionlib.status_tracker as ROS 1 has it, from belvedere's actionlib."""

from belvedere.ros1.actionlib import (
    StatusTracker,
)

__all__ = [
    "StatusTracker",
]
