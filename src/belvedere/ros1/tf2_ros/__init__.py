"""ROS 1's ``tf2_ros`` for the rospy scripts belvedere runs: :class:`Buffer` (tf2's buffer,
belvedere's :class:`~belvedere.tf.TFBuffer` underneath), :class:`TransformListener`,
:class:`TransformBroadcaster`, :class:`StaticTransformBroadcaster`, and tf2's exceptions with
tf2's texts.

Not covered: ``BufferClient`` (the tf2 buffer server's action client) and the ``~tf2_frames``
service a ``Buffer(debug=True)`` offers.
"""

from belvedere.ros1.tf2_ros._buffer import (
    Buffer,
    BufferCore,
    BufferInterface,
    ConvertRegistration,
    Stamped,
    TransformRegistration,
    convert,
)
from belvedere.ros1.tf2_ros._exceptions import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    NotImplementedException,
    TimeoutException,
    TransformException,
    TypeException,
)
from belvedere.ros1.tf2_ros._listener import (
    StaticTransformBroadcaster,
    TransformBroadcaster,
    TransformListener,
)

__all__ = [
    "Buffer",
    "BufferCore",
    "BufferInterface",
    "ConnectivityException",
    "ConvertRegistration",
    "ExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "NotImplementedException",
    "Stamped",
    "StaticTransformBroadcaster",
    "TimeoutException",
    "TransformBroadcaster",
    "TransformException",
    "TransformListener",
    "TransformRegistration",
    "TypeException",
    "convert",
]
