"""Occupancy maps to and from ``nav_msgs/OccupancyGrid`` and ``nav_msgs/MapMetaData``."""

from __future__ import annotations

from typing import Any

import numpy as np

from belvedere.maps._model import OccupancyMap, yaw_from_quat_xyzw
from belvedere.msgs import build, types

__all__ = ["grid_message", "map_from_message", "metadata_message"]


def metadata_message(grid: OccupancyMap, load_time_ns: int = 0) -> Any:
    """The grid's ``nav_msgs/MapMetaData`` (its origin's z is 0, as map_server's)."""
    t = types()
    x, y, _ = grid.origin
    qx, qy, qz, qw = grid.quat_xyzw
    pose = t.cls("geometry_msgs/Pose")(
        t.cls("geometry_msgs/Point")(float(x), float(y), 0.0),
        t.cls("geometry_msgs/Quaternion")(float(qx), float(qy), float(qz), float(qw)),
    )
    return t.cls("nav_msgs/MapMetaData")(
        build.stamp(load_time_ns), float(grid.resolution), grid.width, grid.height, pose
    )


def grid_message(
    grid: OccupancyMap, *, frame_id: str = "map", stamp_ns: int = 0, load_time_ns: int = 0
) -> Any:
    """The grid as a ``nav_msgs/OccupancyGrid`` (``data`` row by row from the origin)."""
    return types().cls("nav_msgs/OccupancyGrid")(
        build.header(stamp_ns, frame_id),
        metadata_message(grid, load_time_ns),
        np.ascontiguousarray(grid.data, dtype=np.int8).reshape(-1),
    )


def map_from_message(msg: Any) -> OccupancyMap:
    """The map a ``nav_msgs/OccupancyGrid`` carries (its origin's orientation kept).

    Raises:
        ValueError: ``data`` does not hold ``width * height`` cells.
    """
    info = msg.info
    width, height = int(info.width), int(info.height)
    data = np.asarray(msg.data, dtype=np.int8).reshape(-1)
    if data.size != width * height:
        text = f"the map is {width} x {height} cells but carries {data.size} values"
        raise ValueError(text)
    q = info.origin.orientation
    p = info.origin.position
    orientation = (float(q.x), float(q.y), float(q.z), float(q.w))
    return OccupancyMap(
        data.reshape(height, width),
        float(info.resolution),
        (float(p.x), float(p.y), yaw_from_quat_xyzw(orientation)),
        orientation,
    )
