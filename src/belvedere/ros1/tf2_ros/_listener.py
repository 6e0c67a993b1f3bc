"""tf2_ros's ``TransformListener`` and broadcasters, over belvedere's rospy: ``/tf`` and
``/tf_static`` carry ``tf2_msgs/TFMessage``."""

from __future__ import annotations

import threading
from typing import Any

from belvedere.ros1 import message_class, rospy

__all__ = ["StaticTransformBroadcaster", "TransformBroadcaster", "TransformListener"]


def _tf_message() -> Any:
    return message_class("tf2_msgs/TFMessage")


class TransformListener:
    """Fills ``buffer`` from ``/tf`` and ``/tf_static`` (the node must be initialised), each
    subscriber calling back on a thread of its own; a jump back in time clears the buffer."""

    def __init__(
        self,
        buffer: Any,
        queue_size: int | None = None,
        buff_size: int = 65536,
        tcp_nodelay: bool = False,
    ) -> None:
        self.buffer = buffer
        self.last_update = rospy.Time.now()
        self.last_update_lock = threading.Lock()
        self.tf_sub = rospy.Subscriber(
            "/tf",
            _tf_message(),
            self.callback,
            queue_size=queue_size,
            buff_size=buff_size,
            tcp_nodelay=tcp_nodelay,
        )
        self.tf_static_sub = rospy.Subscriber(
            "/tf_static",
            _tf_message(),
            self.static_callback,
            queue_size=queue_size,
            buff_size=buff_size,
            tcp_nodelay=tcp_nodelay,
        )

    def __del__(self) -> None:
        if hasattr(self, "tf_static_sub"):
            self.unregister()

    def unregister(self) -> None:
        """Stop listening."""
        self.tf_sub.unregister()
        self.tf_static_sub.unregister()

    def check_for_reset(self) -> None:
        with self.last_update_lock:
            now = rospy.Time.now()
            if now < self.last_update:
                jump = (self.last_update - now).to_sec()
                rospy.logwarn(f"Detected jump back in time of {jump:f}s. Clearing TF buffer.")
                self.buffer.clear()
            self.last_update = now

    @staticmethod
    def _authority(data: Any) -> str:
        header = getattr(data, "_connection_header", None) or {}
        return str(header.get("callerid", "default_authority"))

    def callback(self, data: Any) -> None:
        self.check_for_reset()
        who = self._authority(data)
        for transform in data.transforms:
            self.buffer.set_transform(transform, who)

    def static_callback(self, data: Any) -> None:
        self.check_for_reset()
        who = self._authority(data)
        for transform in data.transforms:
            self.buffer.set_transform_static(transform, who)


class TransformBroadcaster:
    """Sends transforms (one ``TransformStamped`` or a list) on ``/tf``."""

    def __init__(self) -> None:
        self.pub_tf = rospy.Publisher("/tf", _tf_message(), queue_size=100)

    def sendTransform(self, transform: Any) -> None:  # noqa: N802 (tf2_ros's name)
        if not isinstance(transform, list):
            transform = [transform]
        self.pub_tf.publish(_tf_message()(transform))


class StaticTransformBroadcaster:
    """Sends static transforms on ``/tf_static``, latched.

    As in ROS 1's python tf2_ros, each call latches only its own transforms: a listener that
    starts later gets those of the last call alone (send them all in one list)."""

    def __init__(self) -> None:
        self.pub_tf = rospy.Publisher("/tf_static", _tf_message(), queue_size=100, latch=True)

    def sendTransform(self, transform: Any) -> None:  # noqa: N802 (tf2_ros's name)
        if not isinstance(transform, list):
            transform = [transform]
        self.pub_tf.publish(_tf_message()(transform))
