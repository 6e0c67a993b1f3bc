"""hector_mapping: SLAM from the laser alone (:mod:`belvedere.nav.slam`'s hector), with the
ROS node's topics, parameters and transforms.

In: ``scan`` (``~scan_topic``); the laser's pose on the base from TF. Out: ``map`` (latched)
and ``map_metadata`` every ``~map_pub_period``, ``slam_out_pose`` and ``poseupdate``, the
``dynamic_map`` service, and TF ``map → odom`` (from ``odom → base`` at the scan's stamp) when
``~pub_map_odom_transform`` — or ``map → base`` when the odom frame is the base frame, as
hector does for a robot without odometry.
"""

from __future__ import annotations

import logging
import math
from typing import Any

import numpy as np

from belvedere.graph import NS, Node
from belvedere.msgs import message_from_data, types
from belvedere.nav.slam import HectorParams, HectorSlam
from belvedere.nodes._registry import NodeSpec, Session, Starter
from belvedere.tf import TFBuffer, TFError, Transform, TransformBroadcaster, TransformListener

__all__ = ["EXECUTABLES", "PACKAGE"]

PACKAGE = "hector_mapping"

logger = logging.getLogger("belvedere.nodes.hector_mapping")


class _HectorNode:
    def __init__(self, node: Node) -> None:
        self.node = node
        get = node.get_param
        self.base_frame = str(get("~base_frame", "base_link"))
        self.map_frame = str(get("~map_frame", "map_link"))
        self.odom_frame = str(get("~odom_frame", "odom"))
        self.pub_map_odom = bool(get("~pub_map_odom_transform", True))
        self.laser_z = (
            float(get("~laser_z_min_value", -1.0)),
            float(get("~laser_z_max_value", 1.0)),
        )
        self.params = HectorParams(
            resolution=float(get("~map_resolution", 0.025)),
            size=int(get("~map_size", 1024)),
            start_x=float(get("~map_start_x", 0.5)),
            start_y=float(get("~map_start_y", 0.5)),
            levels=max(1, int(get("~map_multi_res_levels", 3))),
            update_free=float(get("~update_factor_free", 0.4)),
            update_occupied=float(get("~update_factor_occupied", 0.9)),
            distance_thresh=float(get("~map_update_distance_thresh", 0.4)),
            angle_thresh=float(get("~map_update_angle_thresh", 0.9)),
            laser_min=float(get("~laser_min_dist", 0.4)),
            laser_max=float(get("~laser_max_dist", 30.0)),
        )
        self.slam = HectorSlam(self.params)
        self.buffer = TFBuffer()
        TransformListener(node, self.buffer)
        self.broadcaster = TransformBroadcaster(node)
        self.map_pub = node.publisher("map", "nav_msgs/OccupancyGrid", queue_size=1, latch=True)
        self.meta_pub = node.publisher(
            "map_metadata", "nav_msgs/MapMetaData", queue_size=1, latch=True
        )
        self.pose_pub = node.publisher("slam_out_pose", "geometry_msgs/PoseStamped", queue_size=1)
        self.update_pub = node.publisher(
            "poseupdate", "geometry_msgs/PoseWithCovarianceStamped", queue_size=1
        )
        scan_topic = str(get("~scan_topic", "scan"))
        node.subscribe(scan_topic, "sensor_msgs/LaserScan", self._on_scan, queue_size=5)
        if bool(get("~advertise_map_service", True)):
            node.service("dynamic_map", "nav_msgs/GetMap", self._on_get_map)
        node.timer(float(get("~map_pub_period", 2.0)), self._publish_map)
        self.last_stamp_ns = 0
        self.map_odom: Transform | None = None
        self._warned: set[str] = set()

    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            logger.warning("%s: %s", self.node.full_name, text)

    def _on_scan(self, msg: Any) -> None:
        stamp_ns = msg.header.stamp.sec * NS + msg.header.stamp.nanosec
        try:
            laser = self.buffer.lookup_transform(self.base_frame, msg.header.frame_id, stamp_ns)
        except TFError:
            try:
                laser = self.buffer.lookup_transform(self.base_frame, msg.header.frame_id, 0)
            except TFError as err:
                self._warn_once("laser", f"no transform from the laser to the base: {err.message}")
                return
        points = _scan_points(
            msg, self.params.laser_min, self.params.laser_max, laser, self.laser_z
        )
        sensor = (laser.translation[0], laser.translation[1])
        pose = self.slam.process(points, sensor)
        self.last_stamp_ns = stamp_ns
        map_base = _planar(pose)
        self._publish_pose(map_base, stamp_ns)
        if self.pub_map_odom:
            self._publish_map_odom(map_base, stamp_ns)

    def _publish_pose(self, map_base: Transform, stamp_ns: int) -> None:
        position = dict(zip("xyz", map_base.translation, strict=True))
        orientation = dict(zip("xyzw", map_base.quat_xyzw, strict=True))
        pose = {"position": position, "orientation": orientation}
        header = {"stamp": _stamp(stamp_ns), "frame_id": self.map_frame}
        self.pose_pub.publish_data({"header": header, "pose": pose})
        cov = np.zeros((6, 6))
        c = self.slam.covariance
        cov[np.ix_([0, 1, 5], [0, 1, 5])] = c
        self.update_pub.publish_data(
            {"header": header, "pose": {"pose": pose, "covariance": cov.reshape(-1).tolist()}}
        )

    def _publish_map_odom(self, map_base: Transform, stamp_ns: int) -> None:
        if self.odom_frame == self.base_frame:
            transform = map_base
            child = self.base_frame
        else:
            try:
                odom_base = self.buffer.lookup_transform(self.odom_frame, self.base_frame, stamp_ns)
            except TFError:
                try:
                    odom_base = self.buffer.lookup_transform(self.odom_frame, self.base_frame, 0)
                except TFError as err:
                    self._warn_once("odom", f"no odometry transform yet: {err.message}")
                    return
            transform = map_base @ odom_base.inverse()
            child = self.odom_frame
        self.map_odom = transform
        self.broadcaster.send(
            self.map_frame, child, transform.translation, transform.quat_xyzw, stamp_ns
        )

    def grid_message(self) -> Any:
        grid = self.slam.map
        cells = grid.cells
        data = np.full(cells.shape, -1, dtype=np.int8)
        data[cells < 0] = 0
        data[cells > 0] = 100
        stamp_ns = self.last_stamp_ns or self.node.now_ns()
        info = {
            "map_load_time": _stamp(stamp_ns),
            "resolution": grid.resolution,
            "width": grid.size,
            "height": grid.size,
            "origin": {
                "position": {"x": grid.origin[0], "y": grid.origin[1], "z": 0.0},
                "orientation": {"w": 1.0},
            },
        }
        msg = message_from_data(
            "nav_msgs/OccupancyGrid",
            {"header": {"stamp": _stamp(stamp_ns), "frame_id": self.map_frame}, "info": info},
        )
        msg.data = data.reshape(-1)
        return msg

    def _publish_map(self) -> None:
        if self.slam.updates == 0:
            return
        msg = self.grid_message()
        self.map_pub.publish(msg)
        self.meta_pub.publish(msg.info)

    def _on_get_map(self, request: Any) -> Any:
        return types().cls("nav_msgs/srv/GetMap_Response")(self.grid_message())


def _stamp(ns: int) -> dict[str, int]:
    return {"sec": ns // NS, "nanosec": ns % NS}


def _planar(pose: np.ndarray[Any, Any]) -> Transform:
    yaw = float(pose[2])
    return Transform(
        (float(pose[0]), float(pose[1]), 0.0), (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
    )


def _scan_points(
    msg: Any,
    range_min: float,
    range_max: float,
    laser: Transform,
    z_limits: tuple[float, float],
) -> np.ndarray[Any, np.dtype[np.float64]]:
    """The scan's valid end points in the base frame (N, 2)."""
    ranges = np.asarray(msg.ranges, dtype=np.float64)
    angles = msg.angle_min + msg.angle_increment * np.arange(len(ranges))
    lo = max(range_min, float(msg.range_min))
    hi = min(range_max, float(msg.range_max))
    ok = np.isfinite(ranges) & (ranges >= lo) & (ranges <= hi)
    r, a = ranges[ok], angles[ok]
    local = np.column_stack((r * np.cos(a), r * np.sin(a), np.zeros(len(r))))
    m = laser.matrix()
    base = local @ m[:3, :3].T + m[:3, 3]
    keep = (base[:, 2] >= z_limits[0]) & (base[:, 2] <= z_limits[1])
    return np.ascontiguousarray(base[keep, :2])


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    _HectorNode(node)


EXECUTABLES: dict[str, Starter] = {"hector_mapping": _start}
