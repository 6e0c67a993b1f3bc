"""Transforms: math (explicit ``quat_xyzw``/``quat_wxyz``), a TF buffer with interpolation,
and the standard TF nodes (robot_state_publisher, joint_state_publisher,
static_transform_publisher, a listener)."""

from belvedere.tf._buffer import TFBuffer, Transformed
from belvedere.tf._errors import (
    TFConnectivityError,
    TFError,
    TFExtrapolationError,
    TFInvalidArgumentError,
    TFLookupError,
)
from belvedere.tf._math import (
    Transform,
    quat_xyzw_from_rpy,
    quat_xyzw_to_matrix,
    rpy_from_quat_xyzw,
    wxyz_from_xyzw,
    xyzw_from_wxyz,
)
from belvedere.tf._nodes import (
    JointStatePublisher,
    RobotStatePublisher,
    TransformBroadcaster,
    TransformListener,
    parse_static_transform_args,
    resolve_tf,
    static_transform_publisher,
)

__all__ = [
    "JointStatePublisher",
    "RobotStatePublisher",
    "TFBuffer",
    "TFConnectivityError",
    "TFError",
    "TFExtrapolationError",
    "TFInvalidArgumentError",
    "TFLookupError",
    "Transform",
    "TransformBroadcaster",
    "TransformListener",
    "Transformed",
    "parse_static_transform_args",
    "quat_xyzw_from_rpy",
    "quat_xyzw_to_matrix",
    "resolve_tf",
    "rpy_from_quat_xyzw",
    "static_transform_publisher",
    "wxyz_from_xyzw",
    "xyzw_from_wxyz",
]
