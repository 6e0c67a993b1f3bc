"""rospy's exception classes, with its names (scripts catch them by these names)."""

from __future__ import annotations

__all__ = [
    "ROSException",
    "ROSInitException",
    "ROSInternalException",
    "ROSInterruptException",
    "ROSSerializationException",
    "ROSTimeMovedBackwardsException",
    "ServiceException",
    "TransportException",
    "TransportInitError",
    "TransportTerminated",
]


class ROSException(Exception):  # noqa: N818 (rospy's names)
    """Base of rospy's errors."""


class ROSSerializationException(ROSException):
    """A message that cannot be serialized (a field of the wrong type)."""


class ROSInitException(ROSException):
    """The node is not initialized (or cannot be)."""


class ROSInterruptException(ROSException, KeyboardInterrupt):
    """Shutdown interrupted a wait (``Rate.sleep``, ``rospy.sleep``, a wait for a message)."""


class ROSTimeMovedBackwardsException(ROSInterruptException):
    """Simulated time jumped back during a sleep (a bag or simulation restarted)."""

    def __init__(self, time: float) -> None:
        super().__init__("ROS time moved backwards")
        self.time = time


class ROSInternalException(Exception):  # noqa: N818
    """A bug in the client library."""


class TransportException(ROSException):
    """A connection failed."""


class TransportTerminated(TransportException):
    """A connection was closed."""


class TransportInitError(TransportException):
    """A connection could not be made."""


class ServiceException(ROSException):
    """A service call failed, or a handler refuses a request."""
