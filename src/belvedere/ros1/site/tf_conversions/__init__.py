"""tf_conversions, as belvedere provides it to the scripts it runs: its ``transformations``
(tf's; ROS's tf2 tutorials use ``tf_conversions.transformations``). ``posemath`` (PyKDL) is
not offered."""

from belvedere.ros1 import transformations as transformations

__all__ = ["transformations"]
