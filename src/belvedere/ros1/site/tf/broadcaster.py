"""tf.broadcaster (belvedere.ros1.tf)."""

from belvedere.ros1.tf import TransformBroadcaster

__all__ = ["TransformBroadcaster"]
