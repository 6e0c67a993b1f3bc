"""tf2_ros.buffer (belvedere.ros1.tf2_ros)."""

from belvedere.ros1.tf2_ros import Buffer

__all__ = ["Buffer"]
