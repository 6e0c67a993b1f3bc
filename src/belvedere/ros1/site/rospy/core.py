"""rospy.core (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import (
    get_node_uri,
    is_shutdown,
    logdebug,
    logdebug_once,
    logdebug_throttle,
    logerr,
    logerr_once,
    logerr_throttle,
    logfatal,
    logfatal_once,
    logfatal_throttle,
    loginfo,
    loginfo_once,
    loginfo_throttle,
    logout,
    logwarn,
    logwarn_once,
    logwarn_throttle,
    signal_shutdown,
)
from belvedere.ros1.rospy._state import (
    add_client_hook as add_client_shutdown_hook,
)
from belvedere.ros1.rospy._state import (
    add_preshutdown_hook,
    add_shutdown_hook,
    is_initialized,
    is_shutdown_requested,
)

__all__ = [
    "add_client_shutdown_hook",
    "add_preshutdown_hook",
    "add_shutdown_hook",
    "get_node_uri",
    "is_initialized",
    "is_shutdown",
    "is_shutdown_requested",
    "logdebug",
    "logdebug_once",
    "logdebug_throttle",
    "logerr",
    "logerr_once",
    "logerr_throttle",
    "logfatal",
    "logfatal_once",
    "logfatal_throttle",
    "loginfo",
    "loginfo_once",
    "loginfo_throttle",
    "logout",
    "logwarn",
    "logwarn_once",
    "logwarn_throttle",
    "signal_shutdown",
]
