"""costmap_2d's ``Costmap2DROS``: a layered costmap on the graph, as move_base holds two.

Parameters under ``~<name>/`` (see :mod:`belvedere.nav.costmap._params`), the static map from
the static layers' ``map_topic`` (latched), observation sources (``LaserScan``,
``PointCloud2``, ``PointCloud``) placed in the global frame with TF at their stamps (a reading
waits, 50 at most, until TF can place it, as tf's message filter does), the robot's pose from
TF (``global_frame`` → ``robot_base_frame``; older than ``transform_tolerance`` is no pose).
Updates run at ``update_frequency`` and publish at ``publish_frequency`` in graph time:
``~<name>/costmap`` (``nav_msgs/OccupancyGrid``, costs translated as costmap_2d's publisher
does), ``~<name>/costmap_updates`` (``map_msgs/OccupancyGridUpdate``, the box that changed)
and ``~<name>/footprint`` (``geometry_msgs/PolygonStamped``, in the global frame).

Readings and poses are data, not trusted geometry (:mod:`belvedere.nav._input`): a scan of
more than 65,536 beams (``SCAN_BEAMS``), with angles that are not finite or a NaN range limit,
a reading whose sensor pose, or a robot pose, that is not finite or farther than 1e8 m
(``POSE_METRES``), and a malformed ``PointCloud2`` are dropped (NaN ranges too); a static map or
a size (``width``/``height``/``resolution``) of more than ``GRID_CELLS`` cells is refused. Each
cause is one counted warning.
"""

from __future__ import annotations

import functools
import logging
import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
import numpy.typing as npt

from belvedere.bounded import GRID_CELLS
from belvedere.graph import NS, Node, Publisher, Subscription
from belvedere.graph._executor import Timer
from belvedere.msgs import build, types
from belvedere.nav._input import Tally, laser_scan_problem, pose_problem
from belvedere.nav.costmap import CostGrid, CostmapParams, LayeredCostmap, Observation
from belvedere.nav.costmap._params import SourceParams
from belvedere.nodes._planar import stamp_ns, yaw_of
from belvedere.tf import TFBuffer, TFError, Transform

__all__ = ["COST_TRANSLATION", "Costmap2DROS", "cloud_points", "scan_points"]

logger = logging.getLogger(__name__)


def _translation() -> npt.NDArray[np.int8]:
    table = np.zeros(256, dtype=np.int8)
    table[1:253] = 1 + (97 * (np.arange(1, 253) - 1)) // 251
    table[253], table[254], table[255] = 99, 100, -1
    return table


COST_TRANSLATION: Final = _translation()
"""costmap_2d_publisher's costs → OccupancyGrid values: 0→0, 1..252→1..98, 253→99, 254→100,
255→-1."""

_PENDING: Final = 50
"""Readings that wait for their transform (tf's message filter queue in the obstacle layer)."""

_MESSAGE_TYPES: Final = {
    "LaserScan": "sensor_msgs/LaserScan",
    "PointCloud2": "sensor_msgs/PointCloud2",
    "PointCloud": "sensor_msgs/PointCloud",
}


def scan_points(scan: Any, *, inf_is_valid: bool) -> npt.NDArray[np.float64]:
    """A scan's points (N, 3) in its frame, as laser_geometry projects them: ranges in
    [range_min, range_max); with ``inf_is_valid`` +inf counts as just under range_max."""
    ranges = np.asarray(scan.ranges, dtype=np.float64)
    if inf_is_valid:
        ranges = np.where(np.isposinf(ranges), float(scan.range_max) - 1e-4, ranges)
    angles = float(scan.angle_min) + np.arange(len(ranges)) * float(scan.angle_increment)
    keep = np.isfinite(ranges) & (ranges >= scan.range_min) & (ranges < scan.range_max)
    r, a = ranges[keep], angles[keep]
    return np.column_stack([r * np.cos(a), r * np.sin(a), np.zeros(len(r))])


def cloud_points(msg: Any) -> npt.NDArray[np.float64]:
    """The finite x, y, z (float32 fields) of a ``sensor_msgs/PointCloud2``.

    Raises:
        ValueError: its layout does not fit its data (a field past ``point_step``, data that
            is not whole points)."""
    offsets = {f.name: int(f.offset) for f in msg.fields}
    if not {"x", "y", "z"} <= set(offsets) or msg.point_step == 0:
        return np.empty((0, 3))
    step = int(msg.point_step)
    if any(not 0 <= offsets[a] <= step - 4 for a in "xyz"):
        message = f"a field x, y or z lies past its point_step of {step}"
        raise ValueError(message)
    count = int(msg.width) * int(msg.height)
    data = np.frombuffer(bytes(msg.data), dtype=np.uint8)[: count * step]
    whole = len(data) - len(data) % step  # (a cut-off last point is not a point)
    rows = data[:whole].reshape(-1, step)
    dtype = ">f4" if msg.is_bigendian else "<f4"
    pts = np.stack(
        [rows[:, offsets[a] : offsets[a] + 4].copy().view(dtype)[:, 0] for a in "xyz"], axis=1
    ).astype(np.float64)
    return pts[np.isfinite(pts).all(axis=1)]


@dataclass
class _Reading:
    source: SourceParams
    msg: Any


class Costmap2DROS:
    """One costmap on the graph (``~<name>/`` of ``node``); ``buffer`` is fed by the owner.

    Raises:
        ValueError: a bad parameter (the message names it).
    """

    def __init__(self, node: Node, name: str, buffer: TFBuffer) -> None:
        self.node = node
        self.name = name
        self.buffer = buffer
        values = node.get_param(f"~{name}", {})
        if not isinstance(values, dict):
            message = f"parameter {name!r} must be a namespace of parameters, not {values!r}"
            raise ValueError(message)
        private = node.get_param("~", {})
        self.params = CostmapParams.from_mapping(
            values, outer=[private] if isinstance(private, dict) else []
        )
        self.costmap = LayeredCostmap(self.params)
        self.costmap_pub: Publisher = node.publisher(
            f"~{name}/costmap", "nav_msgs/OccupancyGrid", queue_size=1, latch=True
        )
        self.updates_pub: Publisher = node.publisher(
            f"~{name}/costmap_updates", "map_msgs/OccupancyGridUpdate", queue_size=1
        )
        self.footprint_pub: Publisher = node.publisher(
            f"~{name}/footprint", "geometry_msgs/PolygonStamped", queue_size=1
        )
        self.subscriptions: list[Subscription] = []
        self.pending: deque[_Reading] = deque()
        self.map_frame = ""
        for layer_name, layer in self.costmap.layers:
            params = getattr(layer, "params", None)
            topic = getattr(params, "map_topic", None)
            if topic is not None:
                self.subscriptions.append(
                    node.subscribe(
                        topic,
                        "nav_msgs/OccupancyGrid",
                        functools.partial(self._on_map, layer=layer_name),
                        queue_size=1,
                    )
                )
        for source_name, layers in self.costmap.sources().items():
            source = layers[0].buffers[source_name].params
            self.subscriptions.append(
                node.subscribe(
                    source.topic,
                    _MESSAGE_TYPES[source.data_type],
                    functools.partial(self._on_reading, source=source),
                    queue_size=_PENDING,
                )
            )
        self.timers: list[Timer] = []
        self.stopped = True
        self._published: CostGrid | None = None
        self._warned: set[str] = set()
        self.tally = Tally(f"{node.full_name}/{name}", logger)
        """Readings and poses skipped or dropped, counted (:mod:`belvedere.nav._input`)."""

    # --- what move_base asks ---------------------------------------------------------------------
    @property
    def global_frame(self) -> str:
        return self.params.global_frame

    @property
    def robot_base_frame(self) -> str:
        return self.params.robot_base_frame

    @property
    def inscribed_radius(self) -> float:
        return self.costmap.inscribed_radius

    @property
    def circumscribed_radius(self) -> float:
        return self.costmap.circumscribed_radius

    def grid(self) -> CostGrid:
        m = self.costmap.master
        return CostGrid(m.costs.copy(), m.resolution, m.origin_x, m.origin_y)

    def footprint(self) -> npt.NDArray[np.float64]:
        return self.costmap.footprint.copy()

    def robot_pose(self) -> npt.NDArray[np.float64] | None:
        """The robot's (x, y, yaw) in the global frame from the latest TF, or None when TF
        cannot tell or the transform is older than ``transform_tolerance``."""
        try:
            stamp, t, q = self.buffer.lookup(self.global_frame, self.robot_base_frame, 0)
        except TFError as err:
            self._warn_once("pose", f"no robot pose: {err.message}")
            return None
        problem = pose_problem([t[0], t[1], yaw_of(q)])
        if problem is not None:
            why, what = problem
            self.tally.add(
                "no robot pose for {count}: it is " + why,
                noun="update",
                first=f"{self.node.now_ns() / NS:.3f} s: {what}",
            )
            return None
        age = self.node.now_ns() - stamp
        if stamp != 0 and age > round(self.params.transform_tolerance * NS):
            self._warn_once(
                "stale",
                f"transform timeout: the robot's pose is {age / NS:.3f} s old "
                f"(transform_tolerance {self.params.transform_tolerance})",
            )
            return None
        return np.array([t[0], t[1], yaw_of(q)])

    def is_current(self) -> bool:
        """Whether every source with an ``expected_update_rate`` sent a reading within it."""
        return self.costmap.current(self.node.now_ns())

    def start(self) -> None:
        """Run updates (and publishing) on graph timers."""
        if not self.stopped:
            return
        self.stopped = False
        if self.params.update_frequency > 0:
            self.timers.append(self.node.timer(1.0 / self.params.update_frequency, self._tick))
        if self.params.publish_frequency > 0:
            self.timers.append(self.node.timer(1.0 / self.params.publish_frequency, self.publish))

    def stop(self) -> None:
        """``shutdown_costmaps``: no updates or publishing until :meth:`start`."""
        self.stopped = True
        for timer in self.timers:
            timer.cancel()
        self.timers.clear()

    def reset(self) -> None:
        """``clear_costmaps``: every layer back to its default."""
        self.costmap.reset()

    def clear_area(self, size: float, layers: Sequence[str], *, invert: bool = False) -> bool:
        """``ClearCostmapRecovery`` on this costmap: the named layers cleared outside (inside,
        with ``invert``) the size x size square at the robot. False without a robot pose."""
        pose = self.robot_pose()
        if pose is None:
            logger.error("%s: cannot clear the costmap: no robot pose", self.name)
            return False
        missing, not_clearable = self.costmap.clear_area(
            float(pose[0]), float(pose[1]), size, layers, invert=invert
        )
        for name in missing:
            self._warn_once(f"clear {name}", f"cannot clear layer {name}: it does not exist")
        for name in not_clearable:
            self._warn_once(f"clear {name}", f"cannot clear layer {name}: it holds no costs")
        return True

    def update_now(self) -> bool:
        """One update: pending readings placed, the grid rebuilt at the robot's pose, the
        footprint published. False when there is no robot pose."""
        self._drain()
        pose = self.robot_pose()
        if pose is None:
            return False
        pose_t = (float(pose[0]), float(pose[1]), float(pose[2]))
        self.costmap.update(pose_t, self.node.now_ns(), map_to_global=self._map_to_global())
        self._publish_footprint(pose_t)
        return True

    # --- inputs ----------------------------------------------------------------------------------
    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            logger.warning("%s/%s: %s", self.node.full_name, self.name, text)

    def _on_map(self, msg: Any, layer: str) -> None:
        info = msg.info
        width, height = int(info.width), int(info.height)
        if width * height > GRID_CELLS:
            self._warn_once(
                "map",
                f"map refused: {width:,} x {height:,} cells, more than the cap of {GRID_CELLS:,}",
            )
            return
        data = np.asarray(msg.data, dtype=np.int8).reshape(-1)
        if data.size != width * height:
            self._warn_once("map", f"a map of {width} x {height} cells carries {data.size}")
            return
        origin = (float(info.origin.position.x), float(info.origin.position.y))
        resolution = float(info.resolution)
        if not (math.isfinite(resolution) and resolution > 0) or pose_problem(origin):
            self._warn_once("map", f"map refused: resolution {resolution}, origin {origin}")
            return
        self.map_frame = str(msg.header.frame_id).lstrip("/")
        self.costmap.set_map(
            data.reshape(height, width), float(info.resolution), origin, self.map_frame, layer=layer
        )

    def _on_reading(self, msg: Any, source: SourceParams) -> None:
        self.pending.append(_Reading(source, msg))
        while len(self.pending) > _PENDING:
            self.pending.popleft()
        self._drain()

    def _drain(self) -> None:
        waiting: deque[_Reading] = deque()
        while self.pending:
            reading = self.pending.popleft()
            if not self._place(reading):
                waiting.append(reading)
        self.pending = waiting

    def _place(self, reading: _Reading) -> bool:
        """Add one reading in the global frame; False while TF cannot place it yet."""
        msg, source = reading.msg, reading.source
        stamp = stamp_ns(msg)
        frame = str(msg.header.frame_id).lstrip("/")
        sensor = source.sensor_frame or frame
        try:
            t_cloud = self.buffer.lookup_transform(self.global_frame, frame, stamp)
            t_sensor = self.buffer.lookup_transform(self.global_frame, sensor, stamp)
        except TFError:
            return False
        at = f"{stamp / NS:.3f} s"
        for t in (t_cloud, t_sensor):
            problem = pose_problem(t.translation)  # (TF refuses NaN and bad rotations)
            if problem is not None:
                why, what = problem
                self.tally.add(
                    "dropped {count} from " + source.name + ": the sensor's pose is " + why,
                    noun="reading",
                    first=f"{at}: {what}",
                )
                return True
        if source.data_type == "LaserScan":
            template = "skipped {count} from " + source.name + ": "
            if self.tally.refused(laser_scan_problem(msg), at=at, template=template):
                return True
            nan = int(np.count_nonzero(np.isnan(np.asarray(msg.ranges))))
            if nan:
                self.tally.add(
                    "dropped {items} in {count} from " + source.name,
                    items=nan,
                    item="NaN range",
                )
            local = scan_points(msg, inf_is_valid=source.inf_is_valid)
        elif source.data_type == "PointCloud2":
            try:
                local = cloud_points(msg)
            except ValueError as err:
                self.tally.add(
                    "dropped {count} from " + source.name + ": " + str(err),
                    noun="cloud",
                    first=at,
                )
                return True
        else:
            local = np.array([[p.x, p.y, p.z] for p in msg.points], dtype=np.float64).reshape(-1, 3)
        points = _apply(t_cloud, local)
        origin = np.asarray(t_sensor.translation, dtype=np.float64)
        self.costmap.add_observation(
            source.name, Observation(origin, points, stamp), self.node.now_ns()
        )
        return True

    def _map_to_global(self) -> tuple[float, float, float] | None:
        if not self.params.rolling_window or not self.map_frame:
            return None
        try:
            t = self.buffer.lookup_transform(self.global_frame, self.map_frame, 0)
        except TFError as err:
            self._warn_once("map_tf", f"cannot place the static map: {err.message}")
            return None
        return (float(t.translation[0]), float(t.translation[1]), yaw_of(t.quat_xyzw))

    # --- outputs ---------------------------------------------------------------------------------
    def _tick(self) -> None:
        if not self.stopped:
            self.update_now()

    def _publish_footprint(self, pose: tuple[float, float, float]) -> None:
        corners = self.costmap.footprint_at(pose)
        cls = types().cls
        point = cls("geometry_msgs/Point32")
        polygon = cls("geometry_msgs/Polygon")([point(float(x), float(y), 0.0) for x, y in corners])
        header = build.header(self.node.now_ns(), self.global_frame)
        self.footprint_pub.publish(cls("geometry_msgs/PolygonStamped")(header, polygon))

    def publish(self) -> None:
        """The whole costmap when its size, resolution or origin changed (or
        ``always_send_full_costmap``), else the box of cells that changed as an update."""
        if self.stopped or not self.costmap.updated:
            return
        grid = self.costmap.master
        last = self._published
        now = self.node.now_ns()
        same_frame = last is not None and (
            last.costs.shape == grid.costs.shape
            and (last.resolution, last.origin_x, last.origin_y)
            == (grid.resolution, grid.origin_x, grid.origin_y)
        )
        if last is None or not same_frame or self.params.always_send_full_costmap:
            self.costmap_pub.publish(self._grid_message(grid, now))
        else:
            changed = np.argwhere(last.costs != grid.costs)
            if len(changed) == 0:
                return
            (j0, i0), (j1, i1) = changed.min(axis=0), changed.max(axis=0) + 1
            box = grid.costs[j0:j1, i0:i1]
            update = types().cls("map_msgs/OccupancyGridUpdate")(
                build.header(now, self.global_frame),
                int(i0),
                int(j0),
                int(i1 - i0),
                int(j1 - j0),
                COST_TRANSLATION[box].reshape(-1),
            )
            self.updates_pub.publish(update)
        self._published = CostGrid(grid.costs.copy(), grid.resolution, grid.origin_x, grid.origin_y)

    def _grid_message(self, grid: CostGrid, now: int) -> Any:
        cls = types().cls
        origin = cls("geometry_msgs/Pose")(
            cls("geometry_msgs/Point")(grid.origin_x, grid.origin_y, 0.0),
            cls("geometry_msgs/Quaternion")(0.0, 0.0, 0.0, 1.0),
        )
        info = cls("nav_msgs/MapMetaData")(
            build.stamp(0), float(grid.resolution), grid.width, grid.height, origin
        )
        return cls("nav_msgs/OccupancyGrid")(
            build.header(now, self.global_frame), info, COST_TRANSLATION[grid.costs].reshape(-1)
        )


def _apply(transform: Transform, points: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    matrix = transform.matrix()
    return points @ matrix[:3, :3].T + matrix[:3, 3]
