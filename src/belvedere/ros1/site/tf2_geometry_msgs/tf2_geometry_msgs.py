"""tf2_geometry_msgs.tf2_geometry_msgs (belvedere.ros1.tf2_geometry_msgs)."""

from belvedere.ros1.tf2_geometry_msgs import *  # noqa: F403
from belvedere.ros1.tf2_geometry_msgs import __all__ as __all__
