"""The occupancy grid as a value: cells, resolution and where the grid lies in its frame."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from belvedere.errors import ParseError

__all__ = [
    "FREE",
    "OCCUPIED",
    "UNKNOWN",
    "MapError",
    "OccupancyMap",
    "quat_xyzw_from_yaw",
    "yaw_from_quat_xyzw",
]

OCCUPIED = 100
FREE = 0
UNKNOWN = -1

Quat = tuple[float, float, float, float]


class MapError(ParseError):
    """A map file (the YAML or its image) that cannot be read, at the line that is wrong."""


def quat_xyzw_from_yaw(yaw: float) -> Quat:
    """The origin's orientation as map_server makes it: tf2's ``setRPY(0, 0, yaw)``, term by
    term (the signs of zero components included)."""
    sr, cr = math.sin(0.0), math.cos(0.0)
    sp, cp = sr, cr
    sy, cy = math.sin(yaw * 0.5), math.cos(yaw * 0.5)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def yaw_from_quat_xyzw(q: Quat) -> float:
    """The yaw map_saver writes for an orientation: tf2's ``Matrix3x3(q).getEulerYPR``.

    An all-zero quaternion (a message's default) is the identity here; tf2 would divide by
    its zero length and write ``-nan``."""
    x, y, z, w = q
    d = x * x + y * y + z * z + w * w
    if d == 0.0:
        return 0.0
    s = 2.0 / d
    ys, zs = y * s, z * s
    wz = w * zs
    xy, xz = x * ys, x * zs
    wy = w * ys
    yy, zz = y * ys, z * zs
    m00 = 1.0 - (yy + zz)
    m10 = xy + wz
    m20 = xz - wy
    if abs(m20) >= 1.0:
        return 0.0  # gimbal lock: tf2 puts all of the rotation in roll
    cos_pitch = math.cos(-math.asin(m20))
    return math.atan2(m10 / cos_pitch, m00 / cos_pitch)


@dataclass(frozen=True, eq=False)
class OccupancyMap:
    """An occupancy grid as ``nav_msgs/OccupancyGrid`` carries it.

    ``data[row, col]`` is the cell ``col`` cells along x and ``row`` cells along y from the
    origin: row 0 is the grid's first row (the bottom of the map's image), as the message's
    ``data`` reshaped to ``(height, width)``. Values are occupancy in percent (0 free, 100
    occupied), -1 unknown (``raw`` maps may hold any int8).
    """

    data: npt.NDArray[np.int8]
    """``(height, width)`` cells."""
    resolution: float
    """Metres per cell (a ``float32`` in the message)."""
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """The pose of cell (0, 0)'s lower-left corner in the map frame: x, y (m) and yaw (rad)."""
    orientation: Quat | None = field(default=None)
    """The origin's orientation as a message carried it; None: made from the yaw as
    map_server makes it (what map_saver writes back is the yaw of this quaternion)."""

    def __post_init__(self) -> None:
        data = np.asarray(self.data)
        if data.ndim != 2:
            msg = f"an occupancy map's cells are a 2-D array, got shape {data.shape}"
            raise ValueError(msg)
        if data.dtype != np.int8:
            data = data.astype(np.int8)
        object.__setattr__(self, "data", data)

    @property
    def width(self) -> int:
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        return int(self.data.shape[0])

    @property
    def quat_xyzw(self) -> Quat:
        """The origin's orientation (the message's, or ``setRPY(0, 0, yaw)``)."""
        if self.orientation is not None:
            return self.orientation
        return quat_xyzw_from_yaw(self.origin[2])

    @property
    def yaw(self) -> float:
        """The origin's yaw as map_saver computes it from the orientation."""
        if self.orientation is None:
            return self.origin[2]
        return yaw_from_quat_xyzw(self.orientation)

    def world_to_cell(self, x: float, y: float) -> tuple[float, float]:
        """Map-frame metres → fractional (column, row) cell coordinates."""
        ox, oy, _ = self.origin
        yaw = self.yaw
        dx, dy = x - ox, y - oy
        c, s = math.cos(yaw), math.sin(yaw)
        return ((c * dx + s * dy) / self.resolution, (-s * dx + c * dy) / self.resolution)
