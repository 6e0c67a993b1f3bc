"""ROS 1's ``tf2_geometry_msgs``: ``do_transform_point``/``_vector3``/``_pose``/
``_pose_with_covariance_stamped``, registered (on import, as there) so that tf2_ros's
``Buffer.transform`` takes ``PointStamped``, ``Vector3Stamped``, ``PoseStamped`` and
``PoseWithCovarianceStamped``.

The original computes with PyKDL frames; this follows KDL's arithmetic (a quaternion's matrix
without normalising it; the quaternion of a matrix with KDL's choice of sign) in plain Python.
Unlike the original, ``do_transform_vector3`` leaves the transform it is given as it was (the
original zeroes its translation). ``transform_to_kdl`` is not offered (no PyKDL).
"""

from __future__ import annotations

import math
from typing import Any

from belvedere.ros1 import message_class
from belvedere.ros1.tf2_ros import ConvertRegistration, TransformRegistration

__all__ = [
    "do_transform_point",
    "do_transform_pose",
    "do_transform_pose_with_covariance_stamped",
    "do_transform_vector3",
    "from_msg_msg",
    "to_msg_msg",
]

Matrix = tuple[tuple[float, float, float], ...]
Vec = tuple[float, float, float]


def to_msg_msg(msg: Any) -> Any:
    return msg


def from_msg_msg(msg: Any) -> Any:
    return msg


def _rotation(x: float, y: float, z: float, w: float) -> Matrix:
    """KDL's ``Rotation::Quaternion`` (a unit quaternion's matrix; not normalised)."""
    x2, y2, z2, w2 = x * x, y * y, z * z, w * w
    return (
        (w2 + x2 - y2 - z2, 2 * x * y - 2 * w * z, 2 * x * z + 2 * w * y),
        (2 * x * y + 2 * w * z, w2 - x2 + y2 - z2, 2 * y * z - 2 * w * x),
        (2 * x * z - 2 * w * y, 2 * y * z + 2 * w * x, w2 - x2 - y2 + z2),
    )


def _apply(m: Matrix, v: Vec) -> Vec:
    return (
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    )


def _product(a: Matrix, b: Matrix) -> Matrix:
    columns = tuple(zip(*b, strict=True))
    return (_apply(columns, a[0]), _apply(columns, a[1]), _apply(columns, a[2]))


def _quaternion(m: Matrix) -> tuple[float, float, float, float]:
    """KDL's ``Rotation::GetQuaternion`` as ``(x, y, z, w)``."""
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 1e-12:
        s = 0.5 / math.sqrt(trace + 1.0)
        return (
            (m[2][1] - m[1][2]) * s,
            (m[0][2] - m[2][0]) * s,
            (m[1][0] - m[0][1]) * s,
            0.25 / s,
        )
    if m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2])
        return 0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s
    if m[1][1] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2])
        return (m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s
    s = 2.0 * math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1])
    return (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s


def _frame(transform: Any) -> tuple[Matrix, Vec]:
    r, t = transform.transform.rotation, transform.transform.translation
    return _rotation(r.x, r.y, r.z, r.w), (t.x, t.y, t.z)


def do_transform_point(point: Any, transform: Any) -> Any:
    """A ``PointStamped`` moved by a ``TransformStamped`` (header: the transform's)."""
    rotation, offset = _frame(transform)
    x, y, z = _apply(rotation, (point.point.x, point.point.y, point.point.z))
    res: Any = message_class("geometry_msgs/PointStamped")()
    res.point.x, res.point.y, res.point.z = x + offset[0], y + offset[1], z + offset[2]
    res.header = transform.header
    return res


def do_transform_vector3(vector3: Any, transform: Any) -> Any:
    """A ``Vector3Stamped`` rotated by a ``TransformStamped`` (its translation left out)."""
    rotation, _ = _frame(transform)
    res: Any = message_class("geometry_msgs/Vector3Stamped")()
    v = vector3.vector
    res.vector.x, res.vector.y, res.vector.z = _apply(rotation, (v.x, v.y, v.z))
    res.header = transform.header
    return res


def _moved_pose(pose: Any, transform: Any) -> tuple[Vec, tuple[float, float, float, float]]:
    rotation, offset = _frame(transform)
    p, q = pose.position, pose.orientation
    x, y, z = _apply(rotation, (p.x, p.y, p.z))
    turned = _product(rotation, _rotation(q.x, q.y, q.z, q.w))
    return (x + offset[0], y + offset[1], z + offset[2]), _quaternion(turned)


def do_transform_pose(pose: Any, transform: Any) -> Any:
    """A ``PoseStamped`` moved by a ``TransformStamped`` (header: the transform's)."""
    (x, y, z), (qx, qy, qz, qw) = _moved_pose(pose.pose, transform)
    res: Any = message_class("geometry_msgs/PoseStamped")()
    res.pose.position.x, res.pose.position.y, res.pose.position.z = x, y, z
    o = res.pose.orientation
    o.x, o.y, o.z, o.w = qx, qy, qz, qw
    res.header = transform.header
    return res


def do_transform_pose_with_covariance_stamped(pose: Any, transform: Any) -> Any:
    """A ``PoseWithCovarianceStamped`` moved by a ``TransformStamped``; the covariance is
    copied as it is (as the original does)."""
    (x, y, z), (qx, qy, qz, qw) = _moved_pose(pose.pose.pose, transform)
    res: Any = message_class("geometry_msgs/PoseWithCovarianceStamped")()
    p = res.pose.pose
    p.position.x, p.position.y, p.position.z = x, y, z
    p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = qx, qy, qz, qw
    res.pose.covariance = pose.pose.covariance
    res.header = transform.header
    return res


def _register() -> None:
    convert = ConvertRegistration()
    for name in ("Vector3Stamped", "PoseStamped", "PointStamped"):
        cls = message_class(f"geometry_msgs/{name}")
        convert.add_to_msg(cls, to_msg_msg)
        convert.add_from_msg(cls, from_msg_msg)
    registry = TransformRegistration()
    registry.add(message_class("geometry_msgs/PointStamped"), do_transform_point)
    registry.add(message_class("geometry_msgs/Vector3Stamped"), do_transform_vector3)
    registry.add(message_class("geometry_msgs/PoseStamped"), do_transform_pose)
    registry.add(
        message_class("geometry_msgs/PoseWithCovarianceStamped"),
        do_transform_pose_with_covariance_stamped,
    )


_register()
