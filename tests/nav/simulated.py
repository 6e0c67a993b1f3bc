"""Test data for SLAM from belvedere's own physics simulation: the course's mbot with its laser
driven once around the cloister (examples/mbot_gazebo/worlds/cloister.world) and on past its
start, so that the run closes a loop.

The diff drive's odometry is the model's true pose (``odometrySource`` world): that is the
ground truth. The odometry the mapper gets is made from it as a wheeled robot's drifts — by
default each step's travel 2 % long, its turn 3 % long, the heading creeping 0.4° a metre, and
a little white noise (seeded); :func:`record` takes other drifts — and recorded, with the
laser's scans and its mount, into a ROS 1 bag as a robot would record ``/scan`` and ``/tf``.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from belvedere.description.urdf import Pose, RobotModel
from belvedere.graph import NS, Graph
from belvedere.maps import OccupancyMap
from belvedere.nav.slam import LaserGeometry
from belvedere.sim.physics import PhysicsSimulation
from belvedere.tf import TFBuffer, TransformListener
from belvedere.world import read_world
from tests.conftest import EXAMPLES

Array = npt.NDArray[np.float64]

WORLD = EXAMPLES / "mbot_gazebo/worlds/cloister.world"
ROBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
START = (0.0, -4.5)
LOOP = [(5.5, -4.5), (5.5, 4.5), (-5.5, 4.5), (-5.5, -4.5), (1.5, -4.5)]
"""The corridors' middle lines, counter-clockwise from the start, and on past it."""
BASE = "base_footprint"
LASER = "laser_link"


@dataclass(frozen=True)
class Recording:
    stamps_ns: list[int]
    scans: list[Any]
    """``sensor_msgs/LaserScan`` messages."""
    truth: Array
    """(S, 3) the base's true pose (x, y, yaw) at each scan, in the world."""
    odom: Array
    """(S, 3) the drifting odometry at each scan (starting at the true start)."""
    laser: tuple[float, float, float]
    """The laser's position on the base (x, y, z)."""


def laser_of(rec: Recording) -> LaserGeometry:
    """The recording's beams, from its first scan, on the laser's place on the base."""
    first = rec.scans[0]
    return LaserGeometry.planar(
        first.angle_min,
        first.angle_increment,
        len(first.ranges),
        first.range_min,
        first.range_max,
        (rec.laser[0], rec.laser[1], 0.0),
    )


def _yaw(q: tuple[float, float, float, float]) -> float:
    x, y, z, w = q
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def _drive(graph: Graph, buffer: TFBuffer) -> Any:
    """A pure-pursuit driver along LOOP on the true pose; stops at the end."""
    node = graph.create_node("driver")
    cmd = node.publisher("/cmd_vel", "geometry_msgs/Twist", queue_size=1)
    state = {"target": 0}

    def tick() -> None:
        try:
            t = buffer.lookup_transform("odom", BASE, 0)
        except Exception:  # noqa: BLE001 - no pose yet
            return
        x, y = t.translation[0], t.translation[1]
        yaw = _yaw(t.quat_xyzw)
        i = state["target"]
        if i >= len(LOOP):
            cmd.publish_data({})
            return
        tx, ty = LOOP[i]
        if math.hypot(tx - x, ty - y) < 0.4:
            state["target"] = i + 1
            return
        err = math.remainder(math.atan2(ty - y, tx - x) - yaw, 2 * math.pi)
        speed = 0.5 if abs(err) < 0.3 else 0.1
        cmd.publish_data({"linear": {"x": speed}, "angular": {"z": max(-1.5, min(1.5, 3 * err))}})

    node.timer(0.1, tick)
    return state


def drift(
    truth: Array, seed: int, *, travel: float = 0.02, turn: float = 0.03, creep: float = 0.4
) -> Array:
    """Odometry from the true poses, drifting as wheel odometry does: each step's travel
    ``travel`` and its turn ``turn`` too long (fractions), the heading creeping ``creep``
    degrees a metre, and a little white noise (seeded)."""
    rng = np.random.default_rng(seed)
    odom = np.zeros_like(truth)
    odom[0] = truth[0]
    for k in range(1, len(truth)):
        a, b = truth[k - 1], truth[k]
        c, s = math.cos(a[2]), math.sin(a[2])
        dx, dy = b[0] - a[0], b[1] - a[1]
        fx, fy = c * dx + s * dy, -s * dx + c * dy  # the step in the robot's frame
        dth = math.remainder(b[2] - a[2], 2 * math.pi)
        dist = math.hypot(fx, fy)
        fx, fy = fx * (1 + travel), fy * (1 + travel)
        dth = dth * (1 + turn) + math.radians(creep) * dist + rng.normal(0.0, 0.002) * (dist > 1e-4)
        fx += rng.normal(0.0, 0.002) * (dist > 1e-4)
        p = odom[k - 1]
        c, s = math.cos(p[2]), math.sin(p[2])
        odom[k] = (p[0] + c * fx - s * fy, p[1] + s * fx + c * fy, p[2] + dth)
    return odom


def record(
    seconds: float = 150.0,
    seed: int = 7,
    *,
    travel: float = 0.02,
    turn: float = 0.03,
    creep: float = 0.4,
) -> Recording:
    """Drive the loop in the physics simulation (simulated time, as fast as it goes), with
    odometry drifting as :func:`drift` makes it. The drive is simulated once per process
    for each ``(seconds, seed)``; other drifts reuse it."""
    rec = _record(seconds, seed)
    return dataclasses.replace(
        rec, odom=drift(rec.truth, seed, travel=travel, turn=turn, creep=creep)
    )


@functools.cache
def _record(seconds: float, seed: int) -> Recording:
    graph = Graph(seed=seed)
    sim = PhysicsSimulation(graph, read_world(WORLD))
    model = RobotModel.from_path(ROBOT)
    sim.spawn(model, name="mbot", pose=Pose(xyz=(START[0], START[1], 0.0)))
    buffer = TFBuffer(cache_time=seconds + 10.0)
    probe = graph.create_node("probe")
    TransformListener(probe, buffer)
    received: list[Any] = []
    probe.subscribe("/scan", "sensor_msgs/LaserScan", received.append, queue_size=100)
    state = _drive(graph, buffer)
    graph.run(duration=seconds, until=lambda: state["target"] >= len(LOOP))
    scans: list[Any] = []
    truth: list[tuple[float, float, float]] = []
    stamps: list[int] = []
    for msg in received:
        ns = msg.header.stamp.sec * NS + msg.header.stamp.nanosec
        if not buffer.can_transform("odom", BASE, ns):
            continue  # before the first odometry, or after the last
        t = buffer.lookup_transform("odom", BASE, ns)
        scans.append(msg)
        stamps.append(ns)
        truth.append((t.translation[0], t.translation[1], _yaw(t.quat_xyzw)))
    laser = _laser_mount(model)
    true = np.array(truth).reshape(-1, 3)
    true[:, 2] = np.unwrap(true[:, 2])
    true.flags.writeable = False  # shared by every drift of this drive
    return Recording(stamps, scans, true, true, laser)


def _laser_mount(model: RobotModel) -> tuple[float, float, float]:
    """The laser's position on the base footprint, along the model's fixed joints."""
    x = y = z = 0.0
    link = LASER
    while link != BASE:
        joint = next(j for j in model.joints if j.child == link)
        ox, oy, oz = joint.origin.xyz
        x, y, z = x + ox, y + oy, z + oz  # the mbot's fixed joints do not rotate
        link = joint.parent
    return (x, y, z)


def write_bag(path: Path, rec: Recording) -> None:
    """``/scan``, ``/tf`` (odom → base_footprint from the drifting odometry, one per scan, at
    its stamp) and ``/tf_static`` (the laser's mount) as a ROS 1 bag."""
    from rosbags.rosbag1 import Writer

    from belvedere.msgs import build, types

    store = types().store
    with Writer(path) as writer:
        tf = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=store)
        static = writer.add_connection(
            "/tf_static", "tf2_msgs/msg/TFMessage", typestore=store, latching=1
        )
        scan = writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=store)
        first = rec.stamps_ns[0]
        mount = build.tf_message(
            [build.transform_stamped(BASE, LASER, rec.laser, (0.0, 0.0, 0.0, 1.0), first)]
        )
        writer.write(static, first, store.serialize_ros1(mount, "tf2_msgs/msg/TFMessage"))
        for ns, msg, (x, y, yaw) in zip(rec.stamps_ns, rec.scans, rec.odom, strict=True):
            q = (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
            odom = build.tf_message([build.transform_stamped("odom", BASE, (x, y, 0.0), q, ns)])
            writer.write(tf, ns, store.serialize_ros1(odom, "tf2_msgs/msg/TFMessage"))
            writer.write(scan, ns, store.serialize_ros1(msg, "sensor_msgs/msg/LaserScan"))


def errors(poses: Array, truth: Array) -> tuple[float, float]:
    """Mean translational error (m) and mean absolute heading error (rad) of the relative
    motions between scans 10 apart (a few metres) and between every scan and the first (the
    whole loop): the relations metric, with the ground truth's relations."""

    def relative(p: Array, i: npt.NDArray[np.int64], j: npt.NDArray[np.int64]) -> Array:
        c, s = np.cos(p[i, 2]), np.sin(p[i, 2])
        dx, dy = p[j, 0] - p[i, 0], p[j, 1] - p[i, 1]
        return np.stack([c * dx + s * dy, -s * dx + c * dy, p[j, 2] - p[i, 2]], axis=1)

    n = len(truth)
    i = np.concatenate([np.arange(n - 10), np.zeros(n - 1, dtype=np.int64)])
    j = np.concatenate([np.arange(10, n), np.arange(1, n)])
    est, true = relative(poses, i, j), relative(truth, i, j)
    d = est - true
    turn = np.abs(np.remainder(d[:, 2] + np.pi, 2 * np.pi) - np.pi)
    return float(np.hypot(d[:, 0], d[:, 1]).mean()), float(turn.mean())


def world_map(resolution: float = 0.05, grow: float = 0.0) -> OccupancyMap:
    """The cloister's walls and pillars rasterised as map_server would load a perfect map:
    a cell is occupied (100) when its centre is in a shape grown by ``grow``, free (0) when
    the robot's start reaches it, else unknown (-1); the grid spans 16 m x 14 m from (-8, -7)."""
    width, height = round(16.0 / resolution), round(14.0 / resolution)
    origin = (-8.0, -7.0)
    cx = origin[0] + (np.arange(width) + 0.5) * resolution
    cy = origin[1] + (np.arange(height) + 0.5) * resolution
    gx, gy = np.meshgrid(cx, cy)
    occupied = np.zeros((height, width), dtype=bool)
    root = ElementTree.parse(WORLD).getroot()
    for link in root.iter("link"):
        pose_el = link.find("pose")
        collision = link.find("collision/geometry")
        if pose_el is None or pose_el.text is None or collision is None:
            continue
        x, y, _, _, _, yaw = (float(v) for v in pose_el.text.split())
        dx, dy = gx - x, gy - y
        c, s = math.cos(yaw), math.sin(yaw)
        u, v = c * dx + s * dy, -s * dx + c * dy  # the cell centre in the shape's frame
        box = collision.find("box/size")
        cylinder = collision.find("cylinder/radius")
        if box is not None and box.text is not None:
            sx, sy, _ = (float(t) for t in box.text.split())
            occupied |= (np.abs(u) <= sx / 2 + grow) & (np.abs(v) <= sy / 2 + grow)
        elif cylinder is not None and cylinder.text is not None:
            occupied |= np.hypot(u, v) <= float(cylinder.text) + grow
    # free where the robot can go (the corridors), unknown elsewhere, as a mapped map
    labels, _ = ndimage.label(~occupied)
    start = labels[
        int((START[1] - origin[1]) / resolution), int((START[0] - origin[0]) / resolution)
    ]
    data = np.full(occupied.shape, -1, dtype=np.int8)
    data[labels == start] = 0
    data[occupied] = 100
    return OccupancyMap(data, resolution, (origin[0], origin[1], 0.0))
