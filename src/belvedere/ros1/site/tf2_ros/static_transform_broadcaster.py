"""tf2_ros.static_transform_broadcaster (belvedere.ros1.tf2_ros)."""

from belvedere.ros1.tf2_ros import StaticTransformBroadcaster

__all__ = ["StaticTransformBroadcaster"]
