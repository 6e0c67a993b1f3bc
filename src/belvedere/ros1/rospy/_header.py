"""``rospy.Header``: std_msgs/Header's class (rospy re-exports it)."""

from belvedere.ros1._classes import message_class

__all__ = ["Header"]

Header = message_class("std_msgs/Header")
