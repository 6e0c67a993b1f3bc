"""Fast constructors for the messages simulations publish many times a second.

:func:`~belvedere.msgs.message_from_data` checks and converts every field (tens of µs per
message); these build the message objects directly (a few µs), for ``/tf``, ``/odom`` and
``/joint_states`` at simulation rates.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.msgs._types import types

__all__ = ["header", "joint_state", "odometry", "stamp", "tf_message", "transform_stamped"]

_NS = 1_000_000_000

Floats = Sequence[float] | npt.NDArray[np.float64]


@cache
def _cls(name: str) -> Any:
    return types().cls(name)


def stamp(ns: int) -> Any:
    """A ``builtin_interfaces/Time`` (ROS 1 ``time``) from nanoseconds."""
    return _cls("builtin_interfaces/Time")(ns // _NS, ns % _NS)


def header(stamp_ns: int, frame_id: str = "", seq: int = 0) -> Any:
    return _cls("std_msgs/Header")(seq, stamp(stamp_ns), frame_id)


def transform_stamped(
    parent: str,
    child: str,
    translation: Floats,
    quat_xyzw: Floats,
    stamp_ns: int,
) -> Any:
    vector = _cls("geometry_msgs/Vector3")
    quat = _cls("geometry_msgs/Quaternion")
    transform = _cls("geometry_msgs/Transform")(
        vector(float(translation[0]), float(translation[1]), float(translation[2])),
        quat(float(quat_xyzw[0]), float(quat_xyzw[1]), float(quat_xyzw[2]), float(quat_xyzw[3])),
    )
    return _cls("geometry_msgs/TransformStamped")(header(stamp_ns, parent), child, transform)


def tf_message(transforms: list[Any]) -> Any:
    return _cls("tf2_msgs/TFMessage")(transforms)


def odometry(
    *,
    stamp_ns: int,
    frame_id: str,
    child_frame_id: str,
    position: Floats,
    quat_xyzw: Floats,
    linear: Floats = (0.0, 0.0, 0.0),
    angular: Floats = (0.0, 0.0, 0.0),
    pose_covariance: Floats | None = None,
    twist_covariance: Floats | None = None,
    seq: int = 0,
) -> Any:
    """A ``nav_msgs/Odometry`` (covariances default to zeros)."""
    vector = _cls("geometry_msgs/Vector3")
    # unpacked and converted one by one: a third of ``*map(float, …)``'s time, at 100 Hz
    px, py, pz = position
    qx, qy, qz, qw = quat_xyzw
    lx, ly, lz = linear
    ax, ay, az = angular
    pose = _cls("geometry_msgs/Pose")(
        _cls("geometry_msgs/Point")(float(px), float(py), float(pz)),
        _cls("geometry_msgs/Quaternion")(float(qx), float(qy), float(qz), float(qw)),
    )
    twist = _cls("geometry_msgs/Twist")(
        vector(float(lx), float(ly), float(lz)), vector(float(ax), float(ay), float(az))
    )
    return _cls("nav_msgs/Odometry")(
        header(stamp_ns, frame_id, seq),
        child_frame_id,
        _cls("geometry_msgs/PoseWithCovariance")(pose, _covariance(pose_covariance)),
        _cls("geometry_msgs/TwistWithCovariance")(twist, _covariance(twist_covariance)),
    )


def _covariance(values: Floats | None) -> Any:
    if values is None:
        return np.zeros(36, dtype=np.float64)
    return np.asarray(values, dtype=np.float64).reshape(36)


def joint_state(
    stamp_ns: int,
    names: Sequence[str],
    positions: Floats,
    velocities: Floats = (),
    efforts: Floats = (),
) -> Any:
    """A ``sensor_msgs/JointState`` (empty velocity/effort arrays when not given)."""
    return _cls("sensor_msgs/JointState")(
        header(stamp_ns),
        list(names),
        np.asarray(positions, dtype=np.float64),
        np.asarray(velocities, dtype=np.float64),
        np.asarray(efforts, dtype=np.float64),
    )
