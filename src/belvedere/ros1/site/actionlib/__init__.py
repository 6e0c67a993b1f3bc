"""``actionlib`` for rospy scripts run by belvedere (ROS 1's names, belvedere's code)."""

from belvedere.ros1.actionlib import *  # noqa: F403
from belvedere.ros1.actionlib import __all__ as __all__
