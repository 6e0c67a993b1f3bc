"""The shapes of a pose's uncertainty, as rviz's Covariance property draws them: an ellipsoid
of the position (two standard deviations each way along its principal axes) and a fan of the
heading (two standard deviations each side) reaching ``offset`` metres ahead of the pose."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from belvedere.tf import Transform

__all__ = ["POSITION_STYLE", "YAW_STYLE", "Mesh", "position_ellipsoids", "yaw_fans"]

F64 = npt.NDArray[np.float64]
Mesh = tuple[npt.NDArray[np.float32], npt.NDArray[np.uint32]]
POSITION_STYLE = ((204, 51, 204), 0.3)
"""rviz's default colour and alpha of the position's covariance."""
YAW_STYLE = ((255, 255, 127), 0.5)
"""… and of the orientation's."""
FLAT = 1e-3
"""The thickness (m) of an ellipsoid whose variance along an axis is zero (a planar robot's
z): a disc, still seen from the side."""
SIGMAS = 2.0


def _sphere(rings: int = 8, segments: int = 16) -> Mesh:
    """A unit sphere: latitude rings between the poles, triangles between them."""
    theta = np.linspace(0.0, math.pi, rings + 1)
    phi = np.linspace(0.0, 2 * math.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    vertices = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)
    faces = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * segments + j, i * segments + (j + 1) % segments
            c, d = a + segments, b + segments
            faces += [(a, c, b), (b, c, d)]
    return vertices.reshape(-1, 3).astype(np.float32), np.asarray(faces, dtype=np.uint32)


_SPHERE = _sphere()


def _joined(parts: list[Mesh]) -> Mesh | None:
    if not parts:
        return None
    offsets = np.cumsum([0] + [len(v) for v, _ in parts[:-1]])
    vertices = np.concatenate([v for v, _ in parts])
    faces = np.concatenate([f + np.uint32(o) for (_, f), o in zip(parts, offsets, strict=True)])
    return vertices.astype(np.float32), faces.astype(np.uint32)


def position_ellipsoids(
    poses: Sequence[tuple[Transform, Sequence[float]]], scale: float = 1.0
) -> Mesh | None:
    """One mesh of the position ellipsoids of ``(pose in the fixed frame, covariance)`` pairs,
    the covariance a row-major 6 x 6 in the pose's parent frame (nav_msgs' convention);
    None when no pose has one (an all-zero covariance shows nothing, as in rviz)."""
    parts: list[Mesh] = []
    for pose, covariance in poses:
        c = np.asarray(covariance, dtype=np.float64).reshape(6, 6)[:3, :3]
        if not np.isfinite(c).all() or not c.any():
            continue
        rotation = pose.matrix()[:3, :3]
        values, axes = np.linalg.eigh(rotation @ ((c + c.T) / 2) @ rotation.T)
        radii = np.maximum(SIGMAS * np.sqrt(np.clip(values, 0.0, None)) * scale, FLAT)
        vertices = (_SPHERE[0] * radii) @ axes.T + np.asarray(pose.translation)
        parts.append((vertices.astype(np.float32), _SPHERE[1]))
    return _joined(parts)


def yaw_fans(
    poses: Sequence[tuple[Transform, Sequence[float]]], offset: float = 1.0, steps: int = 12
) -> Mesh | None:
    """One mesh of the heading fans: flat wedges in the pose's xy plane from its origin to
    ``offset`` metres, two standard deviations of the yaw wide (at most a half turn each side)."""
    parts: list[Mesh] = []
    for pose, covariance in poses:
        variance = float(np.asarray(covariance, dtype=np.float64).reshape(6, 6)[5, 5])
        if not math.isfinite(variance) or variance <= 0:
            continue
        half = min(SIGMAS * math.sqrt(variance), math.pi)
        angles = np.linspace(-half, half, steps + 1)
        rim = np.stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)], axis=1) * offset
        local = np.vstack([np.zeros((1, 3)), rim])
        m = pose.matrix()
        vertices = local @ m[:3, :3].T + m[:3, 3]
        faces = np.array([(0, k, k + 1) for k in range(1, steps + 1)], dtype=np.uint32)
        parts.append((vertices.astype(np.float32), faces))
    return _joined(parts)
