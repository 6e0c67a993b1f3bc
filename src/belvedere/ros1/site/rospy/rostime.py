"""rospy.rostime (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import Duration, Time, get_rostime, get_time

__all__ = ["Duration", "Time", "get_rostime", "get_time"]
