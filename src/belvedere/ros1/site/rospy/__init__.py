"""rospy, as belvedere provides it to the scripts it runs (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import *  # noqa: F403
from belvedere.ros1.rospy import __all__ as __all__
