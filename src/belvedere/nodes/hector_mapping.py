"""hector_mapping: SLAM from the laser alone (:mod:`belvedere.nav.slam`'s hector), with the
ROS node's topics, parameters and transforms.

In: ``scan`` (``~scan_topic``); the laser's pose on the base from TF. Out: ``map`` (latched)
and ``map_metadata`` every ``~map_pub_period``, ``slam_out_pose`` and ``poseupdate``, the
``dynamic_map`` service, and TF ``map → odom`` (from ``odom → base`` at the scan's stamp) when
``~pub_map_odom_transform`` — or ``map → base`` when the odom frame is the base frame, as
hector does for a robot without odometry.

Scans are data, not trusted geometry (:mod:`belvedere.nav._input`): a scan of more than 65,536
beams (``SCAN_BEAMS``), with angles that are not finite or a NaN range limit, or whose laser
mount is not finite or farther than 1e8 m (``POSE_METRES``), is skipped; NaN ranges are
dropped; ``~map_size`` squared may not pass ``GRID_CELLS``. Each cause is one counted warning.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.bounded import GRID_CELLS
from belvedere.graph import NS, Node
from belvedere.maps import OccupancyMap, grid_message
from belvedere.msgs import types
from belvedere.nav._input import Tally, grid_reach, laser_scan_problem
from belvedere.nav.slam import HectorParams, HectorSlam
from belvedere.nodes._planar import planar, stamp_ns, usable_mount, yaw_quat
from belvedere.nodes._registry import (
    NodeSpec,
    ParamLookup,
    Starter,
    TransformClaim,
    stopping_on_bad_values,
)
from belvedere.nodes._slam import Processed
from belvedere.tf import TFBuffer, TFError, Transform, TransformBroadcaster, TransformListener

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE", "PARAMETERS", "TRANSFORMS", "HectorCore"]

PACKAGE = "hector_mapping"

logger = logging.getLogger("belvedere.nodes.hector_mapping")


PARAMETERS: dict[str, Any] = {
    "base_frame": "base_link",
    "map_frame": "map_link",
    "odom_frame": "odom",
    "pub_map_odom_transform": True,
    "laser_z_min_value": -1.0,
    "laser_z_max_value": 1.0,
    "map_resolution": 0.025,
    "map_size": 1024,
    "map_start_x": 0.5,
    "map_start_y": 0.5,
    "map_multi_res_levels": 3,
    "update_factor_free": 0.4,
    "update_factor_occupied": 0.9,
    "map_update_distance_thresh": 0.4,
    "map_update_angle_thresh": 0.9,
    "laser_min_dist": 0.4,
    "laser_max_dist": 30.0,
    "scan_topic": "scan",
    "advertise_map_service": True,
    "map_pub_period": 2.0,
}
"""hector_mapping's parameters with its defaults."""


def _number(params: Mapping[str, Any], name: str, kind: type[float] | type[int]) -> Any:
    value = params[name]
    if isinstance(value, bool) or not isinstance(value, int | float):
        try:
            value = kind(str(value))
        except ValueError:
            message = f"parameter {name} must be a number, got {value!r}"
            raise ValueError(message) from None
    return kind(value)


class HectorCore:
    """hector_mapping's scan handling without the topics: the laser's pose from TF, its end
    points cut to the laser limits, the matcher, the map. ``params`` are the node's
    parameters (names without ``~``); a bad value raises ``ValueError`` naming it."""

    def __init__(self, params: Mapping[str, Any], *, tally: Tally | None = None) -> None:
        self.tally = tally if tally is not None else Tally("hector_mapping", logger)
        """Scans skipped and readings dropped, counted (see :mod:`belvedere.nav._input`)."""
        merged = {**PARAMETERS, **params}
        self.settings = merged
        self.base_frame = str(merged["base_frame"]).lstrip("/")
        self.map_frame = str(merged["map_frame"]).lstrip("/")
        self.odom_frame = str(merged["odom_frame"]).lstrip("/")
        self.laser_z = (
            float(_number(merged, "laser_z_min_value", float)),
            float(_number(merged, "laser_z_max_value", float)),
        )
        self.params = HectorParams(
            resolution=_number(merged, "map_resolution", float),
            size=_number(merged, "map_size", int),
            start_x=_number(merged, "map_start_x", float),
            start_y=_number(merged, "map_start_y", float),
            levels=max(1, _number(merged, "map_multi_res_levels", int)),
            update_free=_number(merged, "update_factor_free", float),
            update_occupied=_number(merged, "update_factor_occupied", float),
            distance_thresh=_number(merged, "map_update_distance_thresh", float),
            angle_thresh=_number(merged, "map_update_angle_thresh", float),
            laser_min=_number(merged, "laser_min_dist", float),
            laser_max=_number(merged, "laser_max_dist", float),
        )
        if self.params.resolution <= 0 or self.params.size < 2:
            message = "parameters map_resolution and map_size must be positive"
            raise ValueError(message)
        if self.params.size**2 > GRID_CELLS:
            message = (
                f"parameter map_size: {self.params.size:,} x {self.params.size:,} cells is more "
                f"than the cap of {GRID_CELLS:,}"
            )
            raise ValueError(message)
        self.slam = HectorSlam(self.params)
        self.processed: list[Processed] = []
        self.last_stamp_ns = 0

    @classmethod
    def names(cls) -> list[str]:
        return list(PARAMETERS)

    throttle_scans = 1

    def wanted(self) -> bool:
        """Every scan is matched (hector has no throttle)."""
        return True

    def ready(self, scan: Any, buffer: TFBuffer) -> bool:
        """Whether the laser's pose on the base is known."""
        frame = scan.header.frame_id
        return buffer.can_transform(self.base_frame, frame, stamp_ns(scan)) or (
            buffer.can_transform(self.base_frame, frame, 0)
        )

    def process(self, scan: Any, buffer: TFBuffer) -> Processed | None:
        """Match one scan whose laser pose is :meth:`ready` (raises TFError if it is not);
        None when it is skipped (counted in :attr:`tally`): more than
        :data:`~belvedere.bounded.SCAN_BEAMS` beams, angles that are not finite, a NaN range
        limit, or a laser mount that is not finite or past
        :data:`~belvedere.bounded.POSE_METRES`. NaN ranges are dropped (counted)."""
        stamp = stamp_ns(scan)
        frame = scan.header.frame_id
        if self.tally.refused(laser_scan_problem(scan), at=f"{stamp / NS:.3f} s"):
            return None
        laser = usable_mount(buffer, self.base_frame, frame, stamp, self.tally)
        if laser is None:
            return None
        ranges = np.asarray(scan.ranges, dtype=np.float64)
        nan = int(np.count_nonzero(np.isnan(ranges)))
        if nan:
            self.tally.add("dropped {items} in {count}", items=nan, item="NaN range")
        p = self.params
        points = _scan_points(
            scan, ranges, p.laser_min, p.laser_max, p.resolution, laser, self.laser_z
        )
        before = self.slam.updates
        pose = self.slam.process(points, (laser.translation[0], laser.translation[1]))
        self.last_stamp_ns = stamp
        try:
            odom = planar(buffer.lookup_transform(self.odom_frame, self.base_frame, stamp))
        except TFError:
            odom = np.full(3, np.nan)
        done = Processed(stamp, pose, odom, self.slam.updates > before)
        self.processed.append(done)
        return done

    def trajectory(self) -> tuple[list[int], npt.NDArray[np.float64]]:
        """The stamps and poses (x, y, yaw) in the map frame of the processed scans."""
        poses = np.array([p.pose for p in self.processed]).reshape(-1, 3)
        return [p.stamp_ns for p in self.processed], poses

    def occupancy(self) -> OccupancyMap | None:
        """The finest level as an occupancy map (hector's trinary cells), None before any."""
        if self.slam.updates == 0:
            return None
        grid = self.slam.map
        cells = grid.cells
        data = np.full(cells.shape, -1, dtype=np.int8)
        data[cells < 0] = 0
        data[cells > 0] = 100
        return OccupancyMap(data, grid.resolution, (grid.origin[0], grid.origin[1], 0.0))

    def summary(self) -> str:
        return f"{self.slam.updates} map updates"


class _HectorNode:
    def __init__(self, node: Node) -> None:
        self.node = node
        params: dict[str, Any] = {}
        for name in PARAMETERS:
            value = node.get_param(f"~{name}", None)
            if value is not None:
                params[name] = value
        self.core = HectorCore(params, tally=Tally(node.full_name, logger))
        core = self.core
        self.base_frame, self.map_frame, self.odom_frame = (
            core.base_frame,
            core.map_frame,
            core.odom_frame,
        )
        self.pub_map_odom = bool(core.settings["pub_map_odom_transform"])
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
        scan_topic = str(core.settings["scan_topic"])
        node.subscribe(scan_topic, "sensor_msgs/LaserScan", self._on_scan, queue_size=5)
        if bool(core.settings["advertise_map_service"]):
            node.service("dynamic_map", "nav_msgs/GetMap", self._on_get_map)
        node.timer(float(_number(core.settings, "map_pub_period", float)), self._publish_map)
        self.map_odom: Transform | None = None
        self._warned: set[str] = set()

    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            logger.warning("%s: %s", self.node.full_name, text)

    def _on_scan(self, msg: Any) -> None:
        if not self.core.ready(msg, self.buffer):
            self._warn_once(
                "laser", f"no transform from the laser ({msg.header.frame_id}) to the base yet"
            )
            return
        done = self.core.process(msg, self.buffer)
        if done is None:
            return
        map_base = _planar(done.pose)
        self._publish_pose(map_base, done.stamp_ns)
        if self.pub_map_odom:
            self._publish_map_odom(map_base, done.stamp_ns)

    def _publish_pose(self, map_base: Transform, stamp_ns: int) -> None:
        position = dict(zip("xyz", map_base.translation, strict=True))
        orientation = dict(zip("xyzw", map_base.quat_xyzw, strict=True))
        pose = {"position": position, "orientation": orientation}
        header = {"stamp": _stamp(stamp_ns), "frame_id": self.map_frame}
        self.pose_pub.publish_data({"header": header, "pose": pose})
        cov = np.zeros((6, 6))
        c = self.core.slam.covariance
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
        grid = self.core.occupancy()
        if grid is None:
            grid = OccupancyMap(np.full((1, 1), -1, dtype=np.int8), self.core.params.resolution)
        stamp = self.core.last_stamp_ns or self.node.now_ns()
        return grid_message(grid, frame_id=self.map_frame, stamp_ns=stamp, load_time_ns=stamp)

    def _publish_map(self) -> None:
        if self.core.slam.updates == 0:
            return
        msg = self.grid_message()
        self.map_pub.publish(msg)
        self.meta_pub.publish(msg.info)

    def _on_get_map(self, request: Any) -> Any:
        return types().cls("nav_msgs/srv/GetMap_Response")(self.grid_message())


def _stamp(ns: int) -> dict[str, int]:
    return {"sec": ns // NS, "nanosec": ns % NS}


def _planar(pose: npt.NDArray[np.float64]) -> Transform:
    return Transform((float(pose[0]), float(pose[1]), 0.0), yaw_quat(float(pose[2])))


def _scan_points(
    msg: Any,
    ranges: npt.NDArray[np.float64],
    range_min: float,
    range_max: float,
    resolution: float,
    laser: Transform,
    z_limits: tuple[float, float],
) -> np.ndarray[Any, np.dtype[np.float64]]:
    """The scan's valid end points in the base frame (N, 2)."""
    angles = msg.angle_min + msg.angle_increment * np.arange(len(ranges))
    lo = max(range_min, float(msg.range_min))
    # (a range past what a grid within GRID_CELLS holds is no use: range_max 1e30)
    hi = min(range_max, float(msg.range_max), grid_reach(resolution))
    ok = np.isfinite(ranges) & (ranges >= lo) & (ranges <= hi)
    r, a = ranges[ok], angles[ok]
    local = np.column_stack((r * np.cos(a), r * np.sin(a), np.zeros(len(r))))
    m = laser.matrix()
    base = local @ m[:3, :3].T + m[:3, 3]
    keep = (base[:, 2] >= z_limits[0]) & (base[:, 2] <= z_limits[1])
    return np.ascontiguousarray(base[keep, :2])


def _claim(spec: NodeSpec, param: ParamLookup) -> list[tuple[str, str]]:
    del spec
    if not param("pub_map_odom_transform", PARAMETERS["pub_map_odom_transform"]):
        return []
    parent = str(param("map_frame", PARAMETERS["map_frame"]))
    odom = str(param("odom_frame", PARAMETERS["odom_frame"]))
    base = str(param("base_frame", PARAMETERS["base_frame"]))
    return [(parent, base if odom == base else odom)]


EXECUTABLES: dict[str, Starter] = {
    "hector_mapping": stopping_on_bad_values(lambda session, spec, node: _HectorNode(node))
}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
TRANSFORMS: dict[str, TransformClaim] = {"hector_mapping": _claim}
