"""Rigid transforms. Quaternions are named by their order: ``quat_xyzw`` (ROS messages) or
``quat_wxyz`` (MuJoCo, viser); roll/pitch/yaw follow URDF (fixed axes x, then y, then z)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

__all__ = [
    "Transform",
    "quat_xyzw_from_rpy",
    "quat_xyzw_to_matrix",
    "rpy_from_quat_xyzw",
    "wxyz_from_xyzw",
    "xyzw_from_wxyz",
]

Quat = tuple[float, float, float, float]
Vec3 = tuple[float, float, float]


def xyzw_from_wxyz(q: Quat) -> Quat:
    return (q[1], q[2], q[3], q[0])


def wxyz_from_xyzw(q: Quat) -> Quat:
    return (q[3], q[0], q[1], q[2])


def quat_xyzw_from_rpy(roll: float, pitch: float, yaw: float) -> Quat:
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def rpy_from_quat_xyzw(q: Quat) -> Vec3:
    x, y, z, w = q
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    s = max(-1.0, min(1.0, 2 * (w * y - z * x)))
    pitch = math.asin(s)
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return (roll, pitch, yaw)


def quat_xyzw_to_matrix(q: Quat) -> npt.NDArray[np.float64]:
    x, y, z, w = q
    n = x * x + y * y + z * z + w * w
    s = 2.0 / n if n > 0 else 0.0
    return np.array(
        [
            [1 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w)],
            [s * (x * y + z * w), 1 - s * (x * x + z * z), s * (y * z - x * w)],
            [s * (x * z - y * w), s * (y * z + x * w), 1 - s * (x * x + y * y)],
        ]
    )


def _quat_mul(a: Quat, b: Quat) -> Quat:
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def _rotate(q: Quat, v: Vec3) -> Vec3:
    x, y, z = (quat_xyzw_to_matrix(q) @ np.asarray(v, dtype=float)).tolist()
    return (x, y, z)


@dataclass(frozen=True, slots=True)
class Transform:
    """``T_parent_child``: where the child frame is, seen from the parent."""

    translation: Vec3 = (0.0, 0.0, 0.0)
    quat_xyzw: Quat = (0.0, 0.0, 0.0, 1.0)

    def __matmul__(self, other: Transform) -> Transform:
        """``T_a_b @ T_b_c = T_a_c``."""
        tx, ty, tz = _rotate(self.quat_xyzw, other.translation)
        a = self.translation
        q = _quat_mul(self.quat_xyzw, other.quat_xyzw)
        return Transform((a[0] + tx, a[1] + ty, a[2] + tz), _normalized(q))

    def inverse(self) -> Transform:
        x, y, z, w = self.quat_xyzw
        conj = (-x, -y, -z, w)
        tx, ty, tz = _rotate(conj, self.translation)
        return Transform((-tx, -ty, -tz), conj)

    def matrix(self) -> npt.NDArray[np.float64]:
        m = np.eye(4)
        m[:3, :3] = quat_xyzw_to_matrix(self.quat_xyzw)
        m[:3, 3] = self.translation
        return m

    @classmethod
    def from_matrix(cls, m: npt.NDArray[np.float64]) -> Transform:
        r = m[:3, :3]
        trace = float(r[0, 0] + r[1, 1] + r[2, 2])
        if trace > 0:
            s = math.sqrt(trace + 1.0) * 2
            q = ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4)
        elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
            s = math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2]) * 2
            q = (s / 4, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s, (r[2, 1] - r[1, 2]) / s)
        elif r[1, 1] > r[2, 2]:
            s = math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2]) * 2
            q = ((r[0, 1] + r[1, 0]) / s, s / 4, (r[1, 2] + r[2, 1]) / s, (r[0, 2] - r[2, 0]) / s)
        else:
            s = math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1]) * 2
            q = ((r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4, (r[1, 0] - r[0, 1]) / s)
        t = m[:3, 3]
        return cls((float(t[0]), float(t[1]), float(t[2])), _normalized(tuple(float(v) for v in q)))  # type: ignore[arg-type]

    def interpolate(self, other: Transform, ratio: float) -> Transform:
        """Linear in translation, spherical in rotation; ``ratio`` 0 → self, 1 → other."""
        a, b = self.translation, other.translation
        t = tuple(a[i] + (b[i] - a[i]) * ratio for i in range(3))
        return Transform((t[0], t[1], t[2]), _slerp(self.quat_xyzw, other.quat_xyzw, ratio))


def _normalized(q: Quat) -> Quat:
    n = math.sqrt(sum(c * c for c in q))
    if n == 0:
        return (0.0, 0.0, 0.0, 1.0)
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def _slerp(a: Quat, b: Quat, t: float) -> Quat:
    dot = sum(x * y for x, y in zip(a, b, strict=True))
    if dot < 0:
        b = (-b[0], -b[1], -b[2], -b[3])
        dot = -dot
    if dot > 0.9995:
        return _normalized(tuple(x + (y - x) * t for x, y in zip(a, b, strict=True)))  # type: ignore[arg-type]
    theta = math.acos(dot)
    s = math.sin(theta)
    wa, wb = math.sin((1 - t) * theta) / s, math.sin(t * theta) / s
    return _normalized(
        (wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2], wa * a[3] + wb * b[3])
    )
