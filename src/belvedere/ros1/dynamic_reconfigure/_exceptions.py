"""The exceptions ROS's ``dynamic_reconfigure`` raises to scripts (ROS's names)."""

from __future__ import annotations

__all__ = ["DynamicReconfigureCallbackException", "DynamicReconfigureParameterException"]


class DynamicReconfigureCallbackException(Exception):  # noqa: N818 (ROS's name)
    """A server's callback returned no configuration, or a ``set_parameters`` call failed."""


class DynamicReconfigureParameterException(Exception):  # noqa: N818 (ROS's name)
    """A change a client cannot make: an unknown parameter, a value of no use."""
