"""Pose arithmetic for worlds: URDF-style poses (xyz + fixed-axis rpy) as 4x4 matrices."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import Pose, transform

__all__ = ["compose", "from_matrix", "inverse", "matrix", "quat_xyzw_to_rpy"]

Matrix4 = npt.NDArray[np.float64]


def matrix(pose: Pose) -> Matrix4:
    return transform(pose)


def from_matrix(m: Matrix4) -> Pose:
    r = m[:3, :3]
    pitch = math.asin(max(-1.0, min(1.0, -float(r[2, 0]))))
    if abs(math.cos(pitch)) > 1e-9:
        roll = math.atan2(float(r[2, 1]), float(r[2, 2]))
        yaw = math.atan2(float(r[1, 0]), float(r[0, 0]))
    else:  # gimbal lock: put everything in yaw
        roll = 0.0
        yaw = math.atan2(-float(r[0, 1]), float(r[1, 1]))
    xyz = (float(m[0, 3]), float(m[1, 3]), float(m[2, 3]))
    return Pose(xyz, (roll, pitch, yaw))


def compose(a: Pose, b: Pose) -> Pose:
    """``a`` then ``b`` (b expressed in a's frame)."""
    return from_matrix(matrix(a) @ matrix(b))


def inverse(pose: Pose) -> Pose:
    inv = np.asarray(np.linalg.inv(matrix(pose)), dtype=np.float64)
    return from_matrix(inv)


def quat_xyzw_to_rpy(x: float, y: float, z: float, w: float) -> tuple[float, float, float]:
    n = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    x, y, z, w = x / n, y / n, z / n, w / n
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return (roll, pitch, yaw)
