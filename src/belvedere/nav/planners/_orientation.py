"""global_planner's ``OrientationFilter``: the yaw of each pose of a plan (``orientation_mode``)."""

from __future__ import annotations

import math
from enum import IntEnum

import numpy as np
import numpy.typing as npt

__all__ = ["OrientationMode", "orient"]


class OrientationMode(IntEnum):
    NONE = 0
    FORWARD = 1
    INTERPOLATE = 2
    FORWARDTHENINTERPOLATE = 3
    BACKWARD = 4
    LEFTWARD = 5
    RIGHTWARD = 6


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


def _along(path: npt.NDArray[np.float64], index: int, window: int) -> float:
    first = max(0, index - window)
    last = min(len(path) - 1, index + window)
    return math.atan2(path[last, 1] - path[first, 1], path[last, 0] - path[first, 0])


def _interpolate(path: npt.NDArray[np.float64], first: int, last: int) -> None:
    start_yaw = float(path[first, 2])
    step = _wrap(float(path[last, 2]) - start_yaw) / (last - first)
    # global_planner scales the step by the absolute index, not the offset from ``first``:
    # kept, so FORWARDTHENINTERPOLATE ends where ROS's does
    for index in range(first, last + 1):
        path[index, 2] = start_yaw + step * index


def orient(
    path: npt.NDArray[np.float64], start_yaw: float, mode: OrientationMode, window: int
) -> None:
    """Set the yaws of ``path`` (N, 3; the last pose is the goal's) in place."""
    count = len(path)
    if count == 0 or mode is OrientationMode.NONE:
        return
    offsets = {
        OrientationMode.FORWARD: 0.0,
        OrientationMode.BACKWARD: math.pi,
        OrientationMode.LEFTWARD: -math.pi / 2,
        OrientationMode.RIGHTWARD: math.pi / 2,
    }
    if mode in offsets:
        for index in range(count - 1):
            path[index, 2] = _wrap(_along(path, index, window) + offsets[mode])
    elif mode is OrientationMode.INTERPOLATE:
        path[0, 2] = start_yaw
        if count > 1:
            _interpolate(path, 0, count - 1)
    else:
        for index in range(count - 1):
            path[index, 2] = _along(path, index, window)
        index = count - 3
        last = float(path[index, 2]) if index >= 0 else 0.0
        while index > 0:
            if abs(_wrap(last - float(path[index - 1, 2]))) > 0.35:
                break
            index -= 1
        path[0, 2] = start_yaw
        if count > 1:
            _interpolate(path, max(index, 0), count - 1)
