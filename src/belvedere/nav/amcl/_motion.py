"""amcl's odometry models: each particle moves by the odometry's step with sampled noise.

``diff`` and ``omni`` are amcl's original models, which pass a *variance* where a standard
deviation belongs (so the noise grows with the square of the motion); ``diff-corrected`` and
``omni-corrected`` take its square root. ``alpha1``-``alpha5`` keep amcl's meanings: rotation
noise from rotation (1) and from translation (2), translation noise from translation (3) and
from rotation (4), strafe noise from translation (5, omni only).
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
import numpy.typing as npt

__all__ = ["ODOM_MODELS", "angle_diff", "sample_motion"]

ODOM_MODELS: Final = ("diff", "omni", "diff-corrected", "omni-corrected")

Poses = npt.NDArray[np.float64]


def angle_diff(a: float, b: float) -> float:
    """a - b wrapped to [-pi, pi] (amcl's ``angle_diff``)."""
    return math.remainder(a - b, 2.0 * math.pi)


def _wrap(angles: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """``(angles + pi) % 2pi - pi``, bit for bit: the remainder of a value already in
    [0, 2pi) is the value itself (fmod is exact), so only the others pay for it."""
    shifted = angles + np.pi
    outside = shifted < 0.0
    outside |= shifted >= 2.0 * np.pi
    if outside.any():
        shifted[outside] %= 2.0 * np.pi
    shifted -= np.pi
    return shifted


def sample_motion(
    model: str,
    alphas: tuple[float, float, float, float, float],
    poses: Poses,
    odom_pose: npt.ArrayLike,
    delta: npt.ArrayLike,
    rng: np.random.Generator,
) -> None:
    """Move ``poses`` (N, 3) in place by the odometry's step ``delta`` (dx, dy in the odometry
    frame, dtheta) that ended at ``odom_pose``; headings stay in [-pi, pi)."""
    a1, a2, a3, a4, a5 = alphas
    dx, dy, dth = (float(v) for v in np.asarray(delta, dtype=np.float64))
    old_theta = float(np.asarray(odom_pose, dtype=np.float64)[2]) - dth
    n = len(poses)
    trans = math.hypot(dx, dy)
    corrected = model.endswith("-corrected")

    def spread(value: float) -> float:
        # amcl's uncorrected models hand the variance to its gaussian as the deviation
        return math.sqrt(max(value, 0.0)) if corrected else value

    if model.startswith("diff"):
        rot1 = 0.0 if trans < 0.01 else angle_diff(math.atan2(dy, dx), old_theta)
        rot2 = angle_diff(dth, rot1)
        # backwards motion is as noisy as forwards
        rot1_noise = min(abs(angle_diff(rot1, 0.0)), abs(angle_diff(rot1, math.pi)))
        rot2_noise = min(abs(angle_diff(rot2, 0.0)), abs(angle_diff(rot2, math.pi)))
        sd_rot1 = spread(a1 * rot1_noise**2 + a2 * trans**2)
        sd_trans = spread(a3 * trans**2 + a4 * rot1_noise**2 + a4 * rot2_noise**2)
        sd_rot2 = spread(a1 * rot2_noise**2 + a2 * trans**2)
        noise = rng.standard_normal((3, n))
        rot1_hat = _wrap(rot1 - sd_rot1 * noise[0])
        trans_hat = trans - sd_trans * noise[1]
        rot2_hat = _wrap(rot2 - sd_rot2 * noise[2])
        heading = poses[:, 2] + rot1_hat
        poses[:, 0] += trans_hat * np.cos(heading)
        poses[:, 1] += trans_hat * np.sin(heading)
        poses[:, 2] = _wrap(heading + rot2_hat)
    elif model.startswith("omni"):
        sd_trans = spread(a3 * trans**2 + a1 * dth**2)
        sd_rot = spread(a4 * dth**2 + a2 * trans**2)
        sd_strafe = spread(a1 * dth**2 + a5 * trans**2)
        bearing = angle_diff(math.atan2(dy, dx), old_theta) + poses[:, 2]
        noise = rng.standard_normal((3, n))
        x_hat = trans + sd_trans * noise[0]
        y_hat = sd_strafe * noise[1]
        rot_hat = dth + sd_rot * noise[2]
        c, s = np.cos(bearing), np.sin(bearing)
        poses[:, 0] += x_hat * c - y_hat * s
        poses[:, 1] += x_hat * s + y_hat * c
        poses[:, 2] = _wrap(poses[:, 2] + rot_hat)
    else:
        msg = f"unknown odometry model {model!r} (one of {', '.join(ODOM_MODELS)})"
        raise ValueError(msg)
