"""Bags for the tests, written with belvedere's writers from messages of known content."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from belvedere.bags import BagWriter, create_writer
from belvedere.bags._model import encode
from belvedere.msgs import message_from_data

MS = 1_000_000


def odometry(i: int) -> Any:
    """The i-th of a 100 Hz odometry stream (stamp i*10 ms + 10 ms)."""
    ns = (i + 1) * 10 * MS
    return message_from_data(
        "nav_msgs/Odometry",
        {
            "header": {
                "seq": i,
                "stamp": {"secs": ns // 1_000_000_000, "nsecs": ns % 1_000_000_000},
                "frame_id": "odom",
            },
            "child_frame_id": "base_footprint",
            "pose": {"pose": {"position": {"x": i * 0.01, "y": -i * 0.02}}},
            "twist": {"twist": {"angular": {"z": 0.5}}},
        },
    )


def scan(i: int) -> Any:
    ranges = np.linspace(0.5, 3.0, 360, dtype=np.float32) + np.float32(i)
    msg = message_from_data(
        "sensor_msgs/LaserScan",
        {"header": {"seq": i, "frame_id": "laser"}, "angle_increment": 0.0174533},
    )
    return replace(msg, ranges=ranges, intensities=ranges * 0)


def write_sample(path: Path, *, compression: str = "none", flush_every: int = 0) -> BagWriter:
    """200 odometry messages (100 Hz), 20 scans (10 Hz) and one latched string; returns the
    writer, closed."""
    writer = create_writer(path, compression=compression)
    enc = writer.encoding
    name = writer.add_connection(
        "/map_name", "std_msgs/msg/String", callerid="/map_server", latching=True
    )
    odom = writer.add_connection(
        "/odom", "nav_msgs/msg/Odometry", callerid="/gazebo", latching=False
    )
    laser = writer.add_connection(
        "/scan", "sensor_msgs/msg/LaserScan", callerid="/gazebo", latching=False
    )
    writer.write(
        name, 5 * MS, encode(message_from_data("std_msgs/String", {"data": "cloister"}), enc)
    )
    for i in range(200):
        writer.write(odom, (i + 1) * 10 * MS, encode(odometry(i), enc))
        if i % 10 == 9:
            writer.write(laser, (i + 1) * 10 * MS, encode(scan(i // 10), enc))
        if flush_every and i % flush_every == flush_every - 1:
            writer.flush()
    writer.close()
    return writer
