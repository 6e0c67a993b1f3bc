"""What the SLAM nodes' cores share: one processed scan, and the planar pose of a transform."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.graph import NS
from belvedere.tf import Transform

__all__ = ["Processed", "planar", "stamp_ns"]


@dataclass(frozen=True)
class Processed:
    """One scan through a mapper: its stamp, the base's pose in the map frame (x, y, yaw),
    the odometry's (NaN where there is none), and whether the scan updated the map."""

    stamp_ns: int
    pose: npt.NDArray[np.float64]
    odom: npt.NDArray[np.float64]
    keyframe: bool


def planar(transform: Transform) -> npt.NDArray[np.float64]:
    """(x, y, yaw) of a transform."""
    x, y, z, w = transform.quat_xyzw
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return np.array([transform.translation[0], transform.translation[1], yaw])


def stamp_ns(msg: Any) -> int:
    """A stamped message's stamp in nanoseconds."""
    stamp = msg.header.stamp
    return int(stamp.sec) * NS + int(stamp.nanosec)
