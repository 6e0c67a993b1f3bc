"""rospy.service (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import ServiceException

__all__ = ["ServiceException"]
