"""tf2_ros.transform_broadcaster (belvedere.ros1.tf2_ros)."""

from belvedere.ros1.tf2_ros import TransformBroadcaster

__all__ = ["TransformBroadcaster"]
