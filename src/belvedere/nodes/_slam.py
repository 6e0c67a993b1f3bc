"""What the SLAM nodes' cores share: one processed scan."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

__all__ = ["Processed"]


@dataclass(frozen=True)
class Processed:
    """One scan through a mapper: its stamp, the base's pose in the map frame (x, y, yaw),
    the odometry's (NaN where there is none), and whether the scan updated the map."""

    stamp_ns: int
    pose: npt.NDArray[np.float64]
    odom: npt.NDArray[np.float64]
    keyframe: bool
