"""ROS 1's ``tf`` for the rospy scripts belvedere runs, as tf has been since it went over to
tf2: :class:`TransformListener` (``lookupTransform``, ``waitForTransform``, ``canTransform``,
``transformPose``, …), :class:`TransformBroadcaster`, the exceptions (``tf.Exception`` is
tf2's ``TransformException``) and :mod:`tf.transformations
<belvedere.ros1.transformations>`.

Not covered: ``Transformer.chain``, the ``tf.msg``/``tf.srv`` modules and ``tfwtf``.
"""

from belvedere.ros1 import transformations
from belvedere.ros1.tf._broadcaster import TransformBroadcaster
from belvedere.ros1.tf._transformer import Transformer, TransformerROS, TransformListener
from belvedere.ros1.tf2_ros import (
    ConnectivityException,
    ExtrapolationException,
    LookupException,
)
from belvedere.ros1.tf2_ros import TransformException as Exception

__all__ = [
    "ConnectivityException",
    "Exception",
    "ExtrapolationException",
    "LookupException",
    "TransformBroadcaster",
    "TransformListener",
    "Transformer",
    "TransformerROS",
    "transformations",
]
