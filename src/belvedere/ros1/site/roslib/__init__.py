"""roslib, as belvedere provides it (belvedere.ros1.roslib)."""

from belvedere.ros1.roslib import *  # noqa: F403
from belvedere.ros1.roslib import __all__ as __all__
