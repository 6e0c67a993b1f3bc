"""depthimage_to_laserscan: the middle rows of a depth image as a LaserScan."""

from __future__ import annotations

from typing import Any

import numpy as np

from belvedere.graph import Node
from belvedere.msgs import types
from belvedere.nodes._registry import NodeSpec, Session, Starter

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "depthimage_to_laserscan"


class _DepthToScan:
    """depthimage_to_laserscan: the middle rows of a depth image as a LaserScan."""

    def __init__(self, node: Node) -> None:
        self.node = node
        self.scan_height = int(node.get_param("~scan_height", 1))
        self.range_min = float(node.get_param("~range_min", 0.45))
        self.range_max = float(node.get_param("~range_max", 10.0))
        self.frame = str(node.get_param("~output_frame_id", "camera_depth_frame"))
        self.info: Any = None
        self.pub = node.publisher("scan", "sensor_msgs/LaserScan", queue_size=10)
        node.subscribe("camera_info", "sensor_msgs/CameraInfo", self._on_info, queue_size=1)
        node.subscribe("image", "sensor_msgs/Image", self._on_image, queue_size=1)

    def _on_info(self, msg: Any) -> None:
        self.info = msg

    def _on_image(self, msg: Any) -> None:
        if self.info is None:
            return
        fx, cx, cy = float(self.info.K[0]), float(self.info.K[2]), float(self.info.K[5])
        if msg.encoding == "16UC1":
            millimetres = np.asarray(msg.data).view(np.uint16).reshape(msg.height, msg.width)
            depth = millimetres.astype(np.float64) / 1000.0
        else:
            metres = np.asarray(msg.data).view(np.float32).reshape(msg.height, msg.width)
            depth = metres.astype(np.float64)
        top = max(0, round(cy) - self.scan_height // 2)
        rows = depth[top : top + self.scan_height].astype(np.float64)
        u = np.arange(msg.width)
        angles = np.arctan2(cx - u, fx)  # left of centre is positive
        stretch = np.sqrt(1.0 + ((u - cx) / fx) ** 2)
        ranges = rows * stretch
        ranges[~np.isfinite(ranges) | (ranges < self.range_min) | (ranges > self.range_max)] = (
            np.inf
        )
        best = ranges.min(axis=0)[::-1]  # increasing angle
        angle_min, angle_max = float(angles[-1]), float(angles[0])
        self.pub.publish(
            types().cls("sensor_msgs/LaserScan")(
                _header(msg.header.stamp, self.frame),
                angle_min,
                angle_max,
                (angle_max - angle_min) / max(1, msg.width - 1),
                0.0,
                0.0,
                self.range_min,
                self.range_max,
                best.astype(np.float32),
                np.zeros(0, dtype=np.float32),
            )
        )


def _header(stamp: Any, frame: str) -> Any:
    return types().cls("std_msgs/Header")(0, stamp, frame)


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    _DepthToScan(node)


EXECUTABLES: dict[str, Starter] = {"depthimage_to_laserscan": _start}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
