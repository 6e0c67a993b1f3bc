"""gmapping: ``slam_gmapping`` with its interface, over :mod:`belvedere.nav.slam`'s mapper.

In: ``scan`` (``sensor_msgs/LaserScan``), odometry from TF (``~odom_frame`` → ``~base_frame``)
at each scan's stamp — a scan waits (five at most, as tf's message filter keeps) until that
transform is known — and the laser's pose on the base from TF. Out: ``map`` (latched) and
``map_metadata`` when a scan was added to the map and ``~map_update_interval`` passed since the
last map, ``~entropy`` then too, TF ``map`` → ``odom`` every ``~transform_publish_period``
(stamped ``~tf_delay`` ahead, as slam_gmapping does), and the ``dynamic_map`` service.
Parameters: slam_gmapping's, with its defaults; see :mod:`belvedere.nav.slam._params` for
what each does here. Those that have no effect here (the particle filter's ``particles`` and
``resampleThreshold``) draw one warning at the node's launch line when they are set.

Scans and odometry are data, not trusted geometry (:mod:`belvedere.nav._input`): a scan of
more than 65,536 beams (``SCAN_BEAMS``), with angles that are not finite or a NaN range limit,
or whose odometry or laser mount is not finite or farther than 1e8 m (``POSE_METRES``), is
skipped; NaN ranges are dropped; ranges are used up to what a grid of ``GRID_CELLS`` cells
holds around the laser (144 m at 5 cm); a scan that would grow a grid past ``GRID_CELLS`` is
left out of the map. Each cause is one warning, counted (again at 10, 100, … times).

:class:`GMappingCore` is the part without topics — scans and a TF buffer in, poses and maps
out — which ``belvedere slam`` runs over a bag.
"""

from __future__ import annotations

import logging
from collections import deque
from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.bounded import LimitError
from belvedere.graph import NS, Node, ServiceFailedError
from belvedere.maps import OccupancyMap, grid_message
from belvedere.msgs import types
from belvedere.nav._input import Tally, laser_scan_problem
from belvedere.nav.slam import GMappingParams, LaserGeometry, SubmapSlam, Tuning
from belvedere.nodes._planar import listen_then, planar, stamp_ns, usable_mount, yaw_quat
from belvedere.nodes._registry import (
    NodeSpec,
    Session,
    Starter,
    TransformClaim,
    frame_claim,
    stopping_on_bad_values,
)
from belvedere.nodes._slam import Processed
from belvedere.tf import TFBuffer, TFError, Transform, TransformBroadcaster

__all__ = [
    "EXECUTABLES",
    "JOINING",
    "NODE_PARAMETERS",
    "PACKAGE",
    "TRANSFORMS",
    "GMappingCore",
    "LaserMountError",
    "Processed",
]

PACKAGE = "gmapping"

logger = logging.getLogger("belvedere.nodes.gmapping")

NODE_PARAMETERS: dict[str, Any] = {
    "base_frame": "base_link",
    "map_frame": "map",
    "odom_frame": "odom",
    "transform_publish_period": 0.05,
}
"""slam_gmapping's own parameters besides GMapping's (``tf_delay`` defaults to the period)."""

_QUEUE = 5
"""Scans waiting for their transform (slam_gmapping's message filter keeps five)."""


class LaserMountError(ValueError):
    """The laser is not mounted level (slam_gmapping refuses such a laser too)."""


def laser_geometry(scan: Any, base_laser: Transform, max_range: float | None) -> LaserGeometry:
    """The scan's beams in the base frame, for a laser at ``base_laser`` on the base."""
    rotation = base_laser.matrix()[:3, :3]
    up = rotation.T @ np.array([0.0, 0.0, 1.0])  # the base's z axis seen from the laser
    if abs(abs(up[2]) - 1.0) > 0.001:
        message = (
            f"the laser (frame {scan.header.frame_id}) is not mounted level: its z axis is "
            f"{up[2]:.3f} of the base's (slam_gmapping needs 1 or -1)"
        )
        raise LaserMountError(message)
    count = len(scan.ranges)
    angles = float(scan.angle_min) + np.arange(count) * float(scan.angle_increment)
    beams = np.stack([np.cos(angles), np.sin(angles), np.zeros(count)], axis=1)
    directions = (beams @ rotation.T)[:, :2]
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return LaserGeometry(
        directions=directions,
        origin=np.array(base_laser.translation[:2], dtype=np.float64),
        range_min=float(scan.range_min),
        range_max=float(scan.range_max),
    )


class GMappingCore:
    """slam_gmapping's scan handling without the topics: throttling, the laser's pose from the
    first scan, odometry from TF at each scan's stamp, the mapper and the map's timing.

    ``params`` are the node's parameters (names without ``~``); unknown ones are ignored, as
    slam_gmapping does; a bad value raises ``ValueError`` naming it."""

    def __init__(
        self,
        params: Mapping[str, Any],
        *,
        tuning: Tuning | None = None,
        tally: Tally | None = None,
    ) -> None:
        self.params = GMappingParams.from_mapping(params)
        self.tally = tally if tally is not None else Tally("slam_gmapping", logger)
        """Scans skipped and readings dropped, counted (see :mod:`belvedere.nav._input`)."""
        self.without_effect = GMappingParams.without_effect(params)
        """What to warn of (once) for the parameters given that have no effect, or None."""
        self.tuning = tuning
        merged = {**NODE_PARAMETERS, **params}
        self.base_frame = str(merged["base_frame"]).lstrip("/")
        self.odom_frame = str(merged["odom_frame"]).lstrip("/")
        self.map_frame = str(merged["map_frame"]).lstrip("/")
        self.slam: SubmapSlam | None = None
        self.scans = 0
        self.laser_frame = ""
        self.last_map_ns: int | None = None
        self.processed: list[Processed] = []

    @classmethod
    def names(cls) -> list[str]:
        """The parameters it reads."""
        return [*GMappingParams.names(), *NODE_PARAMETERS, "tf_delay"]

    @property
    def throttle_scans(self) -> int:
        return self.params.throttle_scans

    def wanted(self) -> bool:
        """Count a scan that arrived; whether it is one ``throttle_scans`` lets through."""
        self.scans += 1
        return self.scans % self.params.throttle_scans == 0

    def ready(self, scan: Any, buffer: TFBuffer) -> bool:
        """Whether the odometry at the scan's stamp is known (tf's message filter's test)."""
        return buffer.can_transform(self.odom_frame, scan.header.frame_id, stamp_ns(scan))

    def process(self, scan: Any, buffer: TFBuffer) -> Processed | None:
        """Map one scan whose transforms are :meth:`ready`; None when it is skipped (counted
        in :attr:`tally`): more than :data:`~belvedere.bounded.SCAN_BEAMS` beams, angles
        that are not finite, a NaN range limit, a laser mount or an odometry pose that is
        not finite or past :data:`~belvedere.bounded.POSE_METRES`, or a beam count other
        than the first scan's.

        Raises:
            TFError: a transform is missing.
            LaserMountError: (first scan) the laser is not level.
        """
        stamp = stamp_ns(scan)
        if self.tally.refused(laser_scan_problem(scan), at=f"{stamp / NS:.3f} s"):
            return None
        odom = planar(buffer.lookup_transform(self.odom_frame, self.base_frame, stamp))
        if self.slam is None:
            frame = scan.header.frame_id
            base_laser = usable_mount(buffer, self.base_frame, frame, stamp, self.tally)
            if base_laser is None:
                return None
            laser = laser_geometry(scan, base_laser, self.params.maxRange)
            self.slam = SubmapSlam(laser, self.params, self.tuning, tally=self.tally)
            self.laser_frame = frame
        result = self.slam.add_scan(stamp / NS, np.asarray(scan.ranges), odom)
        if result is None:
            return None
        done = Processed(stamp_ns=stamp, pose=result.pose, odom=odom, keyframe=result.keyframe)
        self.processed.append(done)
        return done

    def map_due(self, done: Processed) -> bool:
        """slam_gmapping's rule: a new map after a scan that updated it, once
        ``map_update_interval`` passed (by the scans' stamps) since the last one."""
        if not done.keyframe:
            return False
        interval = round(self.params.map_update_interval * NS)
        if self.last_map_ns is not None and done.stamp_ns - self.last_map_ns <= interval:
            return False
        self.last_map_ns = done.stamp_ns
        return True

    def map_to_odom(self) -> npt.NDArray[np.float64]:
        return np.zeros(3) if self.slam is None else self.slam.map_to_odom()

    def occupancy(self) -> OccupancyMap | None:
        return None if self.slam is None else self.slam.occupancy()

    def trajectory(self) -> tuple[list[int], npt.NDArray[np.float64]]:
        """The stamps and poses (x, y, yaw) in the map frame of the processed scans, as the
        pose graph has them now (corrected by the loop closures since)."""
        if self.slam is None:
            return [], np.zeros((0, 3))
        _, poses = self.slam.trajectory()
        return [p.stamp_ns for p in self.processed], poses

    def summary(self) -> str:
        if self.slam is None:
            return ""
        return (
            f"{len(self.slam.keyframes)} added to the map, {self.slam.loop_closures} loop closures"
        )


class _GMappingNode:
    def __init__(self, node: Node) -> None:
        self.node = node
        params: dict[str, Any] = {}
        for name in (*GMappingParams.names(), *NODE_PARAMETERS):
            value = node.get_param(f"~{name}", None)
            if value is not None:
                params[name] = value
        self.core = GMappingCore(params, tally=Tally(node.full_name, logger))
        period = float(node.get_param("~transform_publish_period", 0.05))
        self.tf_delay = float(node.get_param("~tf_delay", period))
        self.buffer = TFBuffer()
        self.broadcaster = TransformBroadcaster(node)
        self.entropy_pub = node.publisher("~entropy", "std_msgs/Float64", queue_size=1, latch=True)
        self.map_pub = node.publisher("map", "nav_msgs/OccupancyGrid", queue_size=1, latch=True)
        self.meta_pub = node.publisher(
            "map_metadata", "nav_msgs/MapMetaData", queue_size=1, latch=True
        )
        node.service("dynamic_map", "nav_msgs/GetMap", self._on_get_map)
        self.pending: deque[Any] = deque()
        listen_then(node, self.buffer, self._drain)
        node.subscribe("scan", "sensor_msgs/LaserScan", self._on_scan, queue_size=5)
        self.map_msg: Any = None
        self._warned: set[str] = set()
        self._failed = False
        if period > 0:
            node.timer(period, self._publish_transform)

    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            logger.warning("%s: %s", self.node.full_name, text)

    def _on_scan(self, msg: Any) -> None:
        if self._failed or not self.core.wanted():
            return
        self.pending.append(msg)
        while len(self.pending) > _QUEUE:
            self.pending.popleft()  # the message filter drops the oldest
        self._drain()

    def _drain(self) -> None:
        while self.pending and self.core.ready(self.pending[0], self.buffer):
            scan = self.pending.popleft()
            try:
                done = self.core.process(scan, self.buffer)
            except TFError as err:
                self._warn_once("tf", f"cannot place the scan, skipped: {err.message}")
                continue
            except ValueError as err:
                self._warn_once("scan", str(err))
                if isinstance(err, LaserMountError):
                    self._failed = True
                    self.pending.clear()
                continue
            if done is not None and self.core.map_due(done):
                self._publish_map(done.stamp_ns)

    def _publish_map(self, stamp_ns: int) -> None:
        try:
            grid = self.core.occupancy()
        except LimitError as err:  # (the keyframes' checks keep it within; a last guard)
            self._warn_once("map", f"no map: {err.message}")
            return
        slam = self.core.slam
        if grid is None or slam is None:
            return
        self.entropy_pub.publish_data({"data": slam.entropy()})
        msg = grid_message(grid, frame_id=self.core.map_frame, stamp_ns=self.node.now_ns())
        self.map_msg = msg
        self.map_pub.publish(msg)
        self.meta_pub.publish(msg.info)

    def _publish_transform(self) -> None:
        x, y, yaw = (float(v) for v in self.core.map_to_odom())
        stamp = self.node.now_ns() + round(self.tf_delay * NS)
        self.broadcaster.send(
            self.core.map_frame, self.core.odom_frame, (x, y, 0.0), yaw_quat(yaw), stamp
        )

    def _on_get_map(self, request: Any) -> Any:
        del request
        if self.map_msg is None:
            raise ServiceFailedError(self.node.resolve("dynamic_map"), "no map yet")
        return types().cls("nav_msgs/srv/GetMap_Response")(self.map_msg)


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    del session
    started = _GMappingNode(node)
    text = started.core.without_effect
    if text is not None:
        if spec.source is not None:
            logger.warning("%s: warning: %s: %s", spec.source, spec.full_name, text)
        else:
            logger.warning("%s: %s", spec.full_name, text)


EXECUTABLES: dict[str, Starter] = {"slam_gmapping": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
TRANSFORMS: dict[str, TransformClaim] = {
    "slam_gmapping": frame_claim(NODE_PARAMETERS, "map_frame", "odom_frame")
}
