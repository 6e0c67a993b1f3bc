"""amcl: adaptive Monte Carlo localization of a laser robot on a known map, as ROS 1's amcl.

In: ``scan`` (``sensor_msgs/LaserScan``; each scan waits, as tf's message filter holds up to
100, until ``~odom_frame_id`` → the scan's frame is known at its stamp), ``initialpose``
(``geometry_msgs/PoseWithCovarianceStamped`` in ``~global_frame_id``), and the map: from the
``static_map`` service (asked every half second until it answers) or, with
``~use_map_topic``, from ``map`` (only the first with ``~first_map_only``).
Out: ``amcl_pose`` (``geometry_msgs/PoseWithCovarianceStamped``, latched, the heaviest
cluster's mean with the whole set's covariance, after each resampling), ``particlecloud``
(``geometry_msgs/PoseArray``, latched, after each filter update, at most ``~gui_publish_rate``
a second when that is positive) and, with ``~tf_broadcast``, TF ``map`` → ``odom`` on every
scan, stamped ``~transform_tolerance`` after it. Services: ``global_localization``,
``request_nomotion_update`` (``std_srvs/Empty``) and ``set_map`` (``nav_msgs/SetMap``).
Every ``1/~save_pose_rate`` seconds the pose is written back to ``~initial_pose_x/y/a`` and
``~initial_cov_xx/yy/aa``, which a new map starts from. The filter's parameters are amcl's
(see :class:`belvedere.nav.amcl.AmclParams`); its randomness comes from the graph's seed.

Scans, odometry, poses and maps are data, not trusted geometry (:mod:`belvedere.nav._input`):
a scan of more than 65,536 beams (``SCAN_BEAMS``), with angles that are not finite or a NaN
range limit, or whose odometry or laser mount is not finite or farther than 1e8 m
(``POSE_METRES``), is skipped (NaN ranges dropped); such an initial pose is ignored; a map of
more than ``GRID_CELLS`` cells, or malformed, is refused (the filter keeps the map it has). A
finite odometry jump is motion, as amcl takes it. Each cause is one counted warning.
"""

from __future__ import annotations

import logging
import math
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.bounded import GRID_CELLS
from belvedere.graph import NS, GraphError, Node
from belvedere.maps import OccupancyMap, map_from_message
from belvedere.msgs import build, types
from belvedere.nav._input import Tally, laser_scan_problem, pose_problem
from belvedere.nav._params import ParamReader, read_like
from belvedere.nav.amcl import AmclMap, AmclParams, Localizer, laser_data
from belvedere.nodes import _reconfigure as reconfigure
from belvedere.nodes._planar import (
    MOUNT_REFUSED,
    laser_mount,
    listen_then,
    planar,
    stamp_ns,
    yaw_of,
    yaw_quat,
)
from belvedere.nodes._registry import (
    Starter,
    TransformClaim,
    frame_claim,
    stopping_on_bad_values,
)
from belvedere.ros1.dynamic_reconfigure.graph_server import GraphServer
from belvedere.tf import TFBuffer, TFError, Transform, TransformBroadcaster

__all__ = [
    "EXECUTABLES",
    "JOINING",
    "NODE_PARAMETERS",
    "PACKAGE",
    "TRANSFORMS",
    "NodeParams",
    "base_bearings",
    "cloud_message",
    "pose_message",
]

PACKAGE = "amcl"

logger = logging.getLogger("belvedere.nodes.amcl")

NODE_PARAMETERS: dict[str, Any] = {
    "odom_frame_id": "odom",
    "base_frame_id": "base_link",
    "global_frame_id": "map",
    "tf_broadcast": True,
    "transform_tolerance": 0.1,
    "gui_publish_rate": -1.0,
    "save_pose_rate": 0.5,
    "use_map_topic": False,
    "first_map_only": False,
}
"""amcl_node's own parameters besides the filter's, with its defaults."""

_QUEUE = 100
"""Scans waiting for their transform (amcl's message filter keeps 100)."""

_MAP_RETRY = 0.5
"""Seconds between requests of ``static_map`` while it does not answer."""

Floats = npt.NDArray[np.float64]


@dataclass(frozen=True)
class NodeParams:
    odom_frame_id: str
    base_frame_id: str
    global_frame_id: str
    tf_broadcast: bool
    transform_tolerance: float
    gui_publish_rate: float
    save_pose_rate: float
    use_map_topic: bool
    first_map_only: bool

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> NodeParams:
        out = read_like(ParamReader(values), NODE_PARAMETERS)
        if out["transform_tolerance"] < 0:
            got = out["transform_tolerance"]
            msg = f"parameter transform_tolerance: expected at least 0, got {got!r}"
            raise ValueError(msg)
        return cls(**out)


def _compose(a: Floats, b: Floats) -> Floats:
    """a ∘ b of planar poses."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return np.array([a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2]])


def _invert(a: Floats) -> Floats:
    c, s = math.cos(a[2]), math.sin(a[2])
    return np.array([-(c * a[0] + s * a[1]), s * a[0] - c * a[1], -a[2]])


def pose_message(frame: str, stamp_ns: int, pose: Floats, covariance: list[float]) -> Any:
    """A ``geometry_msgs/PoseWithCovarianceStamped`` of a planar pose."""
    cls = types().cls
    body = cls("geometry_msgs/Pose")(
        cls("geometry_msgs/Point")(float(pose[0]), float(pose[1]), 0.0),
        cls("geometry_msgs/Quaternion")(*yaw_quat(float(pose[2]))),
    )
    return cls("geometry_msgs/PoseWithCovarianceStamped")(
        build.header(stamp_ns, frame),
        cls("geometry_msgs/PoseWithCovariance")(body, np.asarray(covariance, dtype=np.float64)),
    )


def cloud_message(frame: str, stamp_ns: int, poses: Floats) -> Any:
    """A ``geometry_msgs/PoseArray`` of planar poses (N, 3)."""
    cls = types().cls
    pose, point, quat = (
        cls("geometry_msgs/Pose"),
        cls("geometry_msgs/Point"),
        cls("geometry_msgs/Quaternion"),
    )
    half = poses[:, 2] / 2.0
    rows = zip(
        poses[:, 0].tolist(),
        poses[:, 1].tolist(),
        np.sin(half).tolist(),
        np.cos(half).tolist(),
        strict=True,
    )
    return cls("geometry_msgs/PoseArray")(
        build.header(stamp_ns, frame),
        [pose(point(x, y, 0.0), quat(0.0, 0.0, s, c)) for x, y, s, c in rows],
    )


def base_bearings(mount: Transform, angle_min: float, increment: float) -> tuple[float, float]:
    """A scan's first angle and increment in the base frame, for a laser mounted at
    ``mount`` (base → laser): amcl's way, so a laser mounted upside down counts the other
    way round."""
    rotation = mount.matrix()[:3, :3]

    def base_yaw(angle: float) -> float:
        v = rotation @ np.array([math.cos(angle), math.sin(angle), 0.0])
        return math.atan2(v[1], v[0])

    first = base_yaw(angle_min)
    second = base_yaw(angle_min + increment)
    return first, math.fmod(second - first + 5.0 * math.pi, 2.0 * math.pi) - math.pi


def _map_refusal(msg: Any) -> str | None:
    """Why amcl cannot take a map message, or None: more cells than
    :data:`~belvedere.bounded.GRID_CELLS` (its distance fields are a few times the map),
    cells that are not ``width x height``, a resolution or origin that is not finite."""
    info = msg.info
    width, height = int(info.width), int(info.height)
    if width * height > GRID_CELLS:
        return f"{width:,} x {height:,} cells, more than the cap of {GRID_CELLS:,}"
    if len(msg.data) != width * height:
        return f"{width:,} x {height:,} cells, but it carries {len(msg.data):,} values"
    resolution = float(info.resolution)
    if not (math.isfinite(resolution) and resolution > 0):
        return f"its resolution is {resolution}"
    origin = info.origin.position
    if pose_problem([float(origin.x), float(origin.y)]) is not None:
        return f"its origin ({float(origin.x)}, {float(origin.y)}) is not finite or too far"
    return None


def _read_params(node: Node) -> tuple[AmclParams, NodeParams]:
    values: dict[str, Any] = {}
    for name in (*AmclParams.names(), *NODE_PARAMETERS):
        value = node.get_param(f"~{name}", None)
        if value is not None:
            values[name] = value
    # amcl_node reads this one under a name with a trailing underscore
    for name in ("beam_skip_error_threshold_", "beam_skip_error_threshold"):
        value = node.get_param(f"~{name}", None)
        if value is not None:
            values["beam_skip_error_threshold"] = value
    for name in ("initial_pose_x", "initial_pose_y", "initial_pose_a"):
        value = values.get(name)
        if isinstance(value, float) and math.isnan(value):
            del values[name]  # amcl ignores a NaN initial pose (with a warning)
    for name in ("initial_cov_xx", "initial_cov_yy", "initial_cov_aa"):
        value = values.get(name)
        if isinstance(value, float) and math.isnan(value):
            del values[name]
    return AmclParams.from_mapping(values), NodeParams.from_mapping(values)


class _AmclNode:
    def __init__(self, node: Node) -> None:
        self.node = node
        self.params, self.config = _read_params(node)
        cfg = self.config
        self.buffer = TFBuffer()
        self.broadcaster = TransformBroadcaster(node)
        self.pose_pub = node.publisher(
            "amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", queue_size=2, latch=True
        )
        self.cloud_pub = node.publisher(
            "particlecloud", "geometry_msgs/PoseArray", queue_size=2, latch=True
        )
        node.service("global_localization", "std_srvs/Empty", self._on_global_localization)
        node.service("request_nomotion_update", "std_srvs/Empty", self._on_nomotion)
        node.service("set_map", "nav_msgs/SetMap", self._on_set_map)
        listen_then(node, self.buffer, self._drain)
        node.subscribe("scan", "sensor_msgs/LaserScan", self._on_scan, queue_size=100)
        node.subscribe("initialpose", "geometry_msgs/PoseWithCovarianceStamped", self._on_pose)
        self.localizer: Localizer | None = None
        self.pending: deque[Any] = deque()
        self.lasers: dict[str, tuple[float, float, float]] = {}
        self.initial_pose: tuple[Floats, Floats] | None = None
        self.map_to_odom: Floats | None = None
        self.latest_odom: Floats = np.zeros(3)
        self.last_pose: Any = None
        self.last_cloud_ns: int | None = None
        self.last_save_ns = node.now_ns()
        self.first_map_received = False
        self._warned: set[str] = set()
        self.tally = Tally(node.full_name, logger)
        """Scans, poses and readings skipped or dropped, counted (:mod:`belvedere.nav._input`)."""
        if cfg.use_map_topic:
            node.subscribe("map", "nav_msgs/OccupancyGrid", self._on_map, queue_size=1)
            node.logger.info("Subscribed to map topic.")
        else:
            self._map_timer = node.timer(_MAP_RETRY, self._request_map)
            self._request_map()
        values = reconfigure.current(reconfigure.AMCL, self.params, self.config)
        GraphServer(node, reconfigure.AMCL, values, self._reconfigure)

    def _reconfigure(self, config: dict[str, Any], level: int) -> None:
        """As amcl's: the new parameters, and the filter made anew from the last estimate."""
        params = reconfigure.replaced(self.params, config)
        params.check()
        self.config = NodeParams.from_mapping({**self.config.__dict__, **config})
        self.params = params
        if self.localizer is not None:
            seed = self.node.graph.executor.random.getrandbits(63)
            self.localizer = Localizer(params, self.localizer.map, seed=seed)
            self.pending.clear()
            if self.last_pose is not None:
                self._set_pose(self.last_pose)

    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            logger.warning("%s: %s", self.node.full_name, text)

    # --- the map -----------------------------------------------------------------------------
    def _request_map(self) -> None:
        if self.localizer is not None or self.node.closed:
            return
        try:
            response = self.node.call_service("static_map", "nav_msgs/GetMap", timeout=1.0)
        except GraphError:
            self._warn_once("map", "Request for map failed; trying again...")
            return
        self._map_timer.cancel()
        self._handle_map(response.map)

    def _on_map(self, msg: Any) -> None:
        if self.config.first_map_only and self.first_map_received:
            return
        self._handle_map(msg)

    def _handle_map(self, msg: Any) -> None:
        self.first_map_received = True
        info = msg.info
        self.node.logger.info(
            "Received a %d X %d map @ %.3f m/pix", info.width, info.height, info.resolution
        )
        frame = str(msg.header.frame_id).lstrip("/")
        if frame != self.config.global_frame_id:
            self.node.logger.warning(
                "Frame_id of map received:'%s' doesn't match global_frame_id:'%s'. This could "
                "cause issues with reading published topics",
                frame,
                self.config.global_frame_id,
            )
        refusal = _map_refusal(msg)
        if refusal is not None:
            logger.error("%s: map refused: %s", self.node.full_name, refusal)
            return
        grid: OccupancyMap = map_from_message(msg)
        # a new map starts from the pose last saved to the parameter server
        try:
            self.params, _ = _read_params(self.node)
        except ValueError as err:
            logger.error("%s: %s; keeping the parameters it started with", self.node.full_name, err)
        params = self.params
        seed = self.node.graph.executor.random.getrandbits(63)
        self.localizer = Localizer(params, AmclMap.from_occupancy(grid), seed=seed)
        self.pending.clear()
        if self.initial_pose is not None:
            self.localizer.set_pose(*self.initial_pose)
            self.initial_pose = None

    # --- initial poses and services ----------------------------------------------------------
    def _on_pose(self, msg: Any) -> None:
        frame = str(msg.header.frame_id).lstrip("/")
        if not frame:
            self.node.logger.warning(
                "Received initial pose with empty frame_id.  You should always supply a frame_id."
            )
        elif frame != self.config.global_frame_id:
            self.node.logger.warning(
                'Ignoring initial pose in frame "%s"; initial poses must be in the global '
                'frame, "%s"',
                frame,
                self.config.global_frame_id,
            )
            return
        self._set_pose(msg)

    def _set_pose(self, msg: Any) -> None:
        cfg = self.config
        pose = msg.pose.pose
        q = pose.orientation
        old = np.array([pose.position.x, pose.position.y, yaw_of((q.x, q.y, q.z, q.w))])
        problem = pose_problem(old.tolist())
        if problem is None and not np.isfinite(np.asarray(msg.pose.covariance)).all():
            problem = "not finite", f"covariance {list(msg.pose.covariance)[:2]}…"
        at = f"{stamp_ns(msg) / NS:.3f} s"
        template = "ignored {count}: it is "
        if self.tally.refused(problem, at=at, template=template, noun="initial pose"):
            return
        # where the robot went since the pose's stamp, by the odometry
        try:
            then = planar(
                self.buffer.lookup_transform(cfg.odom_frame_id, cfg.base_frame_id, stamp_ns(msg))
            )
            now = planar(self.buffer.lookup_transform(cfg.odom_frame_id, cfg.base_frame_id, 0))
            moved = _compose(_invert(then), now)
        except TFError:
            moved = np.zeros(3)
        mean = _compose(old, moved)
        cov_in = list(msg.pose.covariance)
        cov = np.zeros((3, 3))
        for i in range(2):
            for j in range(2):
                cov[i, j] = cov_in[6 * i + j]
        cov[2, 2] = cov_in[35]
        self.node.logger.info(
            "Setting pose (%.6f): %.3f %.3f %.3f", self.node.now(), mean[0], mean[1], mean[2]
        )
        if self.localizer is None:
            self.initial_pose = (mean, cov)
        else:
            self.localizer.set_pose(mean, cov)

    def _on_global_localization(self, request: Any) -> None:
        del request
        if self.localizer is None:
            return
        self.node.logger.info("Initializing with uniform distribution")
        self.localizer.global_localization()
        self.node.logger.info("Global initialisation done!")

    def _on_nomotion(self, request: Any) -> None:
        del request
        if self.localizer is not None:
            self.localizer.request_nomotion_update()
            self.node.logger.info("Requesting no-motion update")

    def _on_set_map(self, request: Any) -> dict[str, Any]:
        self._handle_map(request.map)
        self._on_pose(request.initial_pose)
        return {"success": True}

    # --- scans -------------------------------------------------------------------------------
    def _on_scan(self, msg: Any) -> None:
        if self.localizer is None:
            return  # amcl drops scans until it has a map
        self.pending.append(msg)
        while len(self.pending) > _QUEUE:
            self.pending.popleft()
        self._drain()

    def _ready(self, scan: Any) -> bool:
        return self.buffer.can_transform(
            self.config.odom_frame_id, scan.header.frame_id, stamp_ns(scan)
        )

    def _drain(self) -> None:
        """Process every waiting scan whose transform is known now (tf's message filter
        tests each, not only the oldest). Scans older than one processed are dropped: their
        odometry is not coming (it would be older than what the buffer has)."""
        if not self.pending:
            return
        waiting: deque[Any] = deque()
        while self.pending:
            scan = self.pending.popleft()
            if self._ready(scan):
                waiting.clear()
                self._process(scan)
            else:
                waiting.append(scan)
        self.pending = waiting

    def _laser(self, scan: Any) -> tuple[float, float, float] | None:
        """The laser's position on the base (x, y, 0: amcl turns the bearings instead)."""
        frame = str(scan.header.frame_id).lstrip("/")
        known = self.lasers.get(frame)
        if known is not None:
            return known
        base = self.config.base_frame_id
        try:
            mount = laser_mount(self.buffer, base, frame, stamp_ns(scan))
        except TFError as err:
            self._warn_once("laser", f"Couldn't transform from {frame} to {base}: {err}")
            return None
        problem = pose_problem([*mount.translation, *mount.quat_xyzw])
        if problem is not None:
            why, what = problem
            self.tally.add(MOUNT_REFUSED + why, first=what)
            return None
        pose = (float(mount.translation[0]), float(mount.translation[1]), 0.0)
        self.lasers[frame] = pose
        return pose

    def _bearings(self, scan: Any) -> tuple[float, float]:
        mount = self.buffer.lookup_transform(self.config.base_frame_id, scan.header.frame_id, 0)
        return base_bearings(mount, float(scan.angle_min), float(scan.angle_increment))

    def _process(self, scan: Any) -> None:
        localizer = self.localizer
        if localizer is None:
            return
        cfg = self.config
        stamp = stamp_ns(scan)
        if self.tally.refused(laser_scan_problem(scan), at=f"{stamp / NS:.3f} s"):
            return
        laser = self._laser(scan)
        if laser is None:
            return
        try:
            odom = planar(self.buffer.lookup_transform(cfg.odom_frame_id, cfg.base_frame_id, stamp))
            angle_min, increment = self._bearings(scan)
        except TFError as err:
            self._warn_once(
                "odom", f"Couldn't determine robot's pose associated with laser scan: {err}"
            )
            return
        at = f"{stamp / NS:.3f} s"
        if not (math.isfinite(angle_min) and math.isfinite(increment)):  # (its rotation)
            why = "the laser's mount on the base is not finite"
            self.tally.add("skipped {count}: " + why, first=f"{at}: {angle_min}, {increment}")
            return
        problem = pose_problem(odom.tolist())
        if problem is not None:
            why, what = problem
            self.tally.add("skipped {count}: their odometry pose is " + why, first=f"{at}: {what}")
            return
        ranges = np.asarray(scan.ranges, dtype=np.float64)
        nan = int(np.count_nonzero(np.isnan(ranges)))
        if nan:
            self.tally.add("dropped {items} in {count}", items=nan, item="NaN range")
        self.latest_odom = odom
        data = laser_data(
            ranges,
            angle_min,
            increment,
            float(scan.range_min),
            float(scan.range_max),
            laser_min_range=self.params.laser_min_range,
            laser_max_range=self.params.laser_max_range,
        )
        step = localizer.update(odom, data, laser)
        if step.updated:
            self._publish_cloud(localizer)
        if step.estimate is not None:
            pose = step.estimate.pose
            self._publish_pose(stamp, pose, step.estimate.covariance36())
            self.map_to_odom = _compose(pose, _invert(odom))
            self._send_transform(stamp)
        elif self.map_to_odom is not None:
            self._send_transform(stamp)
            self._maybe_save_pose()

    def _send_transform(self, stamp_ns: int) -> None:
        if not self.config.tf_broadcast or self.map_to_odom is None:
            return
        x, y, yaw = (float(v) for v in self.map_to_odom)
        expires = stamp_ns + round(self.config.transform_tolerance * NS)
        self.broadcaster.send(
            self.config.global_frame_id,
            self.config.odom_frame_id,
            (x, y, 0.0),
            yaw_quat(yaw),
            expires,
        )

    def _publish_pose(self, stamp_ns: int, pose: Floats, covariance: list[float]) -> None:
        msg = pose_message(self.config.global_frame_id, stamp_ns, pose, covariance)
        self.pose_pub.publish(msg)
        self.last_pose = msg

    def _publish_cloud(self, localizer: Localizer) -> None:
        if not self.cloud_pub.wanted:
            return
        now = self.node.now_ns()
        rate = self.config.gui_publish_rate
        if rate > 0 and self.last_cloud_ns is not None and now - self.last_cloud_ns < NS / rate:
            return
        self.last_cloud_ns = now
        self.cloud_pub.publish(
            cloud_message(self.config.global_frame_id, now, localizer.filter.poses)
        )

    def _maybe_save_pose(self) -> None:
        rate = self.config.save_pose_rate
        if rate <= 0 or self.map_to_odom is None or self.last_pose is None:
            return
        now = self.node.now_ns()
        if now - self.last_save_ns < NS / rate:
            return
        self.last_save_ns = now
        pose = _compose(self.map_to_odom, self.latest_odom)
        cov = self.last_pose.pose.covariance
        node = self.node
        node.set_param("~initial_pose_x", float(pose[0]))
        node.set_param("~initial_pose_y", float(pose[1]))
        node.set_param("~initial_pose_a", math.remainder(float(pose[2]), 2.0 * math.pi))
        node.set_param("~initial_cov_xx", float(cov[0]))
        node.set_param("~initial_cov_yy", float(cov[7]))
        node.set_param("~initial_cov_aa", float(cov[35]))


EXECUTABLES: dict[str, Starter] = {
    "amcl": stopping_on_bad_values(lambda session, spec, node: _AmclNode(node))
}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
TRANSFORMS: dict[str, TransformClaim] = {
    "amcl": frame_claim(NODE_PARAMETERS, "global_frame_id", "odom_frame_id", when="tf_broadcast")
}
