"""tf's ``TransformBroadcaster``: ``sendTransform(translation, rotation, time, child, parent)``
on ``/tf`` through tf2_ros's broadcaster."""

from __future__ import annotations

from typing import Any

from belvedere.ros1 import message_class, tf2_ros

__all__ = ["TransformBroadcaster"]


class TransformBroadcaster:
    """Sends transforms on ``/tf``."""

    def __init__(self, queue_size: int = 100) -> None:
        del queue_size  # tf2_ros's broadcaster queues 100
        self.tf2_broadcaster = tf2_ros.TransformBroadcaster()

    def sendTransform(  # noqa: N802 (tf's name)
        self, translation: Any, rotation: Any, time: Any, child: str, parent: str
    ) -> None:
        """``child``'s pose in ``parent`` at ``time``: ``translation`` (x, y, z) and
        ``rotation`` (x, y, z, w)."""
        t: Any = message_class("geometry_msgs/TransformStamped")()
        t.header.frame_id = parent
        t.header.stamp = time
        t.child_frame_id = child
        tr, r = t.transform.translation, t.transform.rotation
        tr.x, tr.y, tr.z = translation[0], translation[1], translation[2]
        r.x, r.y, r.z, r.w = rotation[0], rotation[1], rotation[2], rotation[3]
        self.sendTransformMessage(t)

    def sendTransformMessage(self, transform: Any) -> None:  # noqa: N802
        """One ``geometry_msgs/TransformStamped``."""
        self.tf2_broadcaster.sendTransform([transform])
