"""tf2_geometry_msgs, as belvedere provides it to the scripts it runs
(belvedere.ros1.tf2_geometry_msgs; importing it registers the message types with
tf2_ros.Buffer.transform)."""

from belvedere.ros1.tf2_geometry_msgs import *  # noqa: F403
from belvedere.ros1.tf2_geometry_msgs import __all__ as __all__
