"""rospy.core (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import (
    is_shutdown,
    logdebug,
    logerr,
    logfatal,
    loginfo,
    logwarn,
    signal_shutdown,
)

__all__ = ["is_shutdown", "logdebug", "logerr", "logfatal", "loginfo", "logwarn", "signal_shutdown"]
