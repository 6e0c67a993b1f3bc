"""Scans and odometry for the tests of untrusted input: a robot in a 10 m square room, its
laser 0.1 m ahead of the base, as clean messages any of which a test can spoil (NaN angles,
a 1e7 m odometry jump, 70,000 beams…), and bags of them.

Built in the test from numbers: no recorded data.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.graph import NS
from belvedere.msgs import build, types

HALF = 5.0
"""The room's walls are at x, y = ±HALF."""
LASER = (0.1, 0.0, 0.2)
"""The laser on the base (x, y, z), not turned."""
BEAMS = 360

Pose = tuple[float, float, float]


def room_ranges(pose: Pose, count: int = BEAMS) -> npt.NDArray[np.float32]:
    """What the laser at ``pose`` of the base sees of the room: ``count`` beams over a turn,
    the first at -pi."""
    x, y, yaw = pose
    lx = x + LASER[0] * math.cos(yaw)
    ly = y + LASER[0] * math.sin(yaw)
    angles = yaw - math.pi + (2 * math.pi / count) * np.arange(count)
    c, s = np.cos(angles), np.sin(angles)
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = np.where(c > 0, (HALF - lx) / c, np.where(c < 0, (-HALF - lx) / c, np.inf))
        ty = np.where(s > 0, (HALF - ly) / s, np.where(s < 0, (-HALF - ly) / s, np.inf))
    return np.minimum(tx, ty).astype(np.float32)


def path(count: int, step: float = 0.1) -> list[Pose]:
    """The base's poses along a slow arc inside the room, one per scan."""
    return [
        (-2.0 + step * i * 0.5, 1.5 * math.sin(step * i * 0.3), 0.15 * step * i)
        for i in range(count)
    ]


def scan(
    stamp_ns: int,
    ranges: npt.ArrayLike,
    *,
    angle_min: float = -math.pi,
    increment: float | None = None,
    range_min: float = 0.1,
    range_max: float = 30.0,
    frame: str = "laser",
) -> Any:
    """A ``sensor_msgs/LaserScan``."""
    with np.errstate(over="ignore"):  # (a huge range is inf on the wire, as in a bag)
        values = np.asarray(ranges, dtype=np.float32)
    step = 2 * math.pi / max(len(values), 1) if increment is None else increment
    return types().cls("sensor_msgs/LaserScan")(
        build.header(stamp_ns, frame),
        float(angle_min),
        float(angle_min + step * max(len(values) - 1, 0)),
        float(step),
        0.0,
        0.1,
        float(range_min),
        float(range_max),
        values,
        np.zeros(0, dtype=np.float32),
    )


def quat(yaw: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))


def tf(parent: str, child: str, pose: Sequence[float], stamp_ns: int) -> Any:
    """A ``tf2_msgs/TFMessage`` of one planar transform (x, y, yaw)."""
    x, y, yaw = (float(v) for v in pose)
    rotation = quat(yaw) if math.isfinite(yaw) else (0.0, 0.0, 0.0, 1.0)
    return build.tf_message(
        [build.transform_stamped(parent, child, (x, y, 0.0), rotation, stamp_ns)]
    )


def mount(stamp_ns: int, translation: Sequence[float] = LASER) -> Any:
    """The static transform base_link → laser."""
    return build.tf_message(
        [build.transform_stamped("base_link", "laser", translation, (0, 0, 0, 1), stamp_ns)]
    )


Spoil = Callable[[int, Pose, Any], tuple[Pose, Any]]
"""(scan index, odometry pose, scan message) → what is sent instead."""


def write_bag(
    path_: Path,
    count: int,
    spoil: Spoil | None = None,
    *,
    beams: int = BEAMS,
    start_ns: int = NS,
) -> None:
    """A ROS 1 bag: ``/tf_static`` (the laser's mount), then per scan ``/tf`` (odom →
    base_link at its stamp) and ``/scan``, 10 a second; ``spoil`` may replace either."""
    from rosbags.rosbag1 import Writer

    store = types().store
    with Writer(path_) as writer:
        tf_conn = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=store)
        static = writer.add_connection(
            "/tf_static", "tf2_msgs/msg/TFMessage", typestore=store, latching=1
        )
        scans = writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=store)
        writer.write(
            static, start_ns, store.serialize_ros1(mount(start_ns), "tf2_msgs/msg/TFMessage")
        )
        for i, pose in enumerate(path(count)):
            ns = start_ns + i * NS // 10
            msg = scan(ns, room_ranges(pose, beams))
            if spoil is not None:
                pose, msg = spoil(i, pose, msg)
            odom = tf("odom", "base_link", pose, ns)
            writer.write(tf_conn, ns, store.serialize_ros1(odom, "tf2_msgs/msg/TFMessage"))
            writer.write(scans, ns, store.serialize_ros1(msg, "sensor_msgs/msg/LaserScan"))
