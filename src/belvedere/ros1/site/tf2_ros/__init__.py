"""tf2_ros, as belvedere provides it to the scripts it runs (belvedere.ros1.tf2_ros)."""

from belvedere.ros1.tf2_ros import *  # noqa: F403
from belvedere.ros1.tf2_ros import __all__ as __all__
