"""Rigid motions of the plane as ``(x, y, theta)`` arrays, vectorized over leading axes."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = ["between", "compose", "inverse", "transform_points", "wrap"]

Array = npt.NDArray[np.float64]


def wrap(angle: Array | float) -> Array:
    """Angles folded into [-pi, pi)."""
    return np.asarray((np.asarray(angle) + np.pi) % (2.0 * np.pi) - np.pi, dtype=np.float64)


def compose(a: Array, b: Array) -> Array:
    """``a ∘ b``: the pose ``b``, given in ``a``'s frame, expressed in ``a``'s parent frame."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    x = a[..., 0] + c * b[..., 0] - s * b[..., 1]
    y = a[..., 1] + s * b[..., 0] + c * b[..., 1]
    return np.stack([x, y, wrap(a[..., 2] + b[..., 2])], axis=-1)


def inverse(a: Array) -> Array:
    a = np.asarray(a, dtype=np.float64)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    x = -(c * a[..., 0] + s * a[..., 1])
    y = s * a[..., 0] - c * a[..., 1]
    return np.stack([x, y, wrap(-a[..., 2])], axis=-1)


def between(a: Array, b: Array) -> Array:
    """``a⁻¹ ∘ b``: ``b`` seen from ``a``."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    dx = b[..., 0] - a[..., 0]
    dy = b[..., 1] - a[..., 1]
    return np.stack([c * dx + s * dy, -s * dx + c * dy, wrap(b[..., 2] - a[..., 2])], axis=-1)


def transform_points(pose: Array, points: Array) -> Array:
    """Points ``(N, 2)`` given in ``pose``'s frame, in the parent frame."""
    c, s = np.cos(pose[2]), np.sin(pose[2])
    x = points[:, 0]
    y = points[:, 1]
    return np.stack([pose[0] + c * x - s * y, pose[1] + s * x + c * y], axis=1)
