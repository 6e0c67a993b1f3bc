"""The planar view the 2-D navigation nodes take of stamps, rotations and transforms."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.graph import NS
from belvedere.tf import Transform

__all__ = ["planar", "stamp_ns", "yaw_of", "yaw_quat"]


def stamp_ns(msg: Any) -> int:
    """A stamped message's stamp in nanoseconds."""
    stamp = msg.header.stamp
    return int(stamp.sec) * NS + int(stamp.nanosec)


def yaw_of(quat_xyzw: tuple[float, float, float, float]) -> float:
    """The rotation about z of a quaternion (x, y, z, w)."""
    # the yaw alone: these nodes read it per scan or reading, and never need roll or pitch
    x, y, z, w = quat_xyzw
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def yaw_quat(yaw: float) -> tuple[float, float, float, float]:
    """The quaternion (x, y, z, w) of a rotation by ``yaw`` about z."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def planar(transform: Transform) -> npt.NDArray[np.float64]:
    """(x, y, yaw) of a transform."""
    return np.array(
        [transform.translation[0], transform.translation[1], yaw_of(transform.quat_xyzw)]
    )
