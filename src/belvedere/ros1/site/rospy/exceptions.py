"""rospy.exceptions (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import (
    ROSException,
    ROSInitException,
    ROSInternalException,
    ROSInterruptException,
    ROSSerializationException,
    ROSTimeMovedBackwardsException,
    TransportException,
    TransportInitError,
    TransportTerminated,
)

__all__ = [
    "ROSException",
    "ROSInitException",
    "ROSInternalException",
    "ROSInterruptException",
    "ROSSerializationException",
    "ROSTimeMovedBackwardsException",
    "TransportException",
    "TransportInitError",
    "TransportTerminated",
]
