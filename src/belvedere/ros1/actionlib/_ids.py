"""Goal ids as actionlib's servers make them for goals that come without one:
``<name>-<n>-<secs>.<nsecs>``, numbered per process."""

from __future__ import annotations

import itertools
import threading
from typing import Any

from belvedere.ros1 import rospy
from belvedere.ros1.actionlib._states import GoalID

__all__ = ["GoalIDGenerator"]

_count = itertools.count(1)
_count_lock = threading.Lock()


class GoalIDGenerator:
    """Makes unique ``GoalID``s prefixed with ``name`` (by default this node's name)."""

    def __init__(self, name: str | None = None) -> None:
        self.name = rospy.get_name() if name is None else name

    def set_name(self, name: str) -> None:
        self.name = name

    def generate_ID(self) -> Any:  # noqa: N802 (actionlib's name)
        now = rospy.Time.now()
        with _count_lock:
            n = next(_count)
        return GoalID(id=f"{self.name}-{n}-{now.secs}.{now.nsecs}", stamp=now)
