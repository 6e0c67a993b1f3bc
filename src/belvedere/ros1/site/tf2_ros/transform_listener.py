"""tf2_ros.transform_listener (belvedere.ros1.tf2_ros)."""

from belvedere.ros1.tf2_ros import TransformListener

__all__ = ["TransformListener"]
