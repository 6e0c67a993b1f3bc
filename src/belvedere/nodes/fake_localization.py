"""fake_localization: a perfect localizer for simulations, from the simulator's true pose.

In: ``base_pose_ground_truth`` (``nav_msgs/Odometry``, the base's true pose; rbx1's
fake_amcl.launch remaps it to ``odom``) — each message waits, as tf's message filter holds up
to 100, until ``~odom_frame_id`` → ``~base_frame_id`` is known at its stamp — and
``initialpose`` (``geometry_msgs/PoseWithCovarianceStamped``), which shifts the offset so
that the current pose becomes the one given. Out: ``amcl_pose`` (latched, zero covariance),
``particlecloud`` (latched, the one pose) and TF ``~global_frame_id`` → ``~odom_frame_id``
that puts the base at the true pose, stamped ``~transform_tolerance`` ahead. ``~delta_x``,
``~delta_y`` and ``~delta_yaw`` are where the map's origin is in the simulator's frame. A true
pose or an initial pose that is not finite or farther than 1e8 m (``POSE_METRES``) is skipped,
counted.
"""

from __future__ import annotations

import logging
import math
from collections import deque
from typing import Any

from belvedere.graph import NS, Node
from belvedere.nav._input import Tally, pose_problem
from belvedere.nav._params import ParamReader, read_like
from belvedere.nodes._planar import listen_then, stamp_ns
from belvedere.nodes._registry import (
    Starter,
    TransformClaim,
    frame_claim,
    stopping_on_bad_values,
)
from belvedere.tf import TFBuffer, TFError, Transform, TransformBroadcaster, quat_xyzw_from_rpy

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE", "PARAMETERS", "TRANSFORMS"]

PACKAGE = "fake_localization"

logger = logging.getLogger("belvedere.nodes.fake_localization")

PARAMETERS: dict[str, Any] = {
    "odom_frame_id": "odom",
    "base_frame_id": "base_link",
    "global_frame_id": "/map",
    "delta_x": 0.0,
    "delta_y": 0.0,
    "delta_yaw": 0.0,
    "transform_tolerance": 0.1,
}
"""fake_localization's parameters with its defaults."""

_QUEUE = 100


def _pose_transform(pose: Any) -> Transform:
    p, q = pose.position, pose.orientation
    return Transform((p.x, p.y, p.z), (q.x, q.y, q.z, q.w))


def _pose_problem(pose: Any) -> tuple[str, str] | None:
    """Why a ``geometry_msgs/Pose`` cannot be used (:func:`~belvedere.nav._input.pose_problem`;
    a quaternion of length 0 too), or None."""
    p, q = pose.position, pose.orientation
    values = [float(v) for v in (p.x, p.y, p.z, q.x, q.y, q.z, q.w)]
    problem = pose_problem(values)
    if problem is None and not sum(v * v for v in values[3:]) > 1e-12:
        return "not a rotation", f"quaternion {tuple(values[3:])}"
    return problem


def _read(node: Node) -> dict[str, Any]:
    values = {name: node.get_param(f"~{name}", default) for name, default in PARAMETERS.items()}
    return read_like(ParamReader(values), PARAMETERS)


class _FakeLocalization:
    def __init__(self, node: Node) -> None:
        self.node = node
        params = _read(node)
        self.odom_frame: str = params["odom_frame_id"]
        self.base_frame: str = params["base_frame_id"]
        self.global_frame: str = params["global_frame_id"]
        self.tolerance_ns = round(float(params["transform_tolerance"]) * NS)
        yaw = -float(params["delta_yaw"])
        self.offset = Transform(
            (-float(params["delta_x"]), -float(params["delta_y"]), 0.0),
            quat_xyzw_from_rpy(0.0, 0.0, yaw),
        )
        self.buffer = TFBuffer()
        self.broadcaster = TransformBroadcaster(node)
        self.pose_pub = node.publisher(
            "amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", queue_size=1, latch=True
        )
        self.cloud_pub = node.publisher(
            "particlecloud", "geometry_msgs/PoseArray", queue_size=1, latch=True
        )
        self.pending: deque[Any] = deque()
        self.pending_pose: Any = None
        self.tally = Tally(node.full_name, logger)
        """Poses skipped, counted (:mod:`belvedere.nav._input`)."""
        listen_then(node, self.buffer, self._drain)
        node.subscribe(
            "base_pose_ground_truth", "nav_msgs/Odometry", self._on_truth, queue_size=100
        )
        node.subscribe(
            "initialpose", "geometry_msgs/PoseWithCovarianceStamped", self._on_pose, queue_size=1
        )

    def _on_truth(self, msg: Any) -> None:
        self.pending.append(msg)
        while len(self.pending) > _QUEUE:
            self.pending.popleft()
        self._drain()

    def _on_pose(self, msg: Any) -> None:
        self.pending_pose = msg  # the message filter keeps one
        self._drain()

    def _drain(self) -> None:
        waiting: deque[Any] = deque()
        while self.pending:
            msg = self.pending.popleft()
            if self.buffer.can_transform(self.base_frame, self.odom_frame, stamp_ns(msg)):
                waiting.clear()  # older ones' transforms are not coming
                self._update(msg)
            else:
                waiting.append(msg)  # tf's message filter tests each message
        self.pending = waiting
        pose = self.pending_pose
        if pose is not None:
            frame = str(pose.header.frame_id).lstrip("/") or self.global_frame
            if self.buffer.can_transform(self.global_frame, frame, stamp_ns(pose)):
                self.pending_pose = None
                self._shift(pose)

    def _update(self, msg: Any) -> None:
        stamp = stamp_ns(msg)
        problem = _pose_problem(msg.pose.pose)
        if problem is not None:
            why, what = problem
            self.tally.add(
                "skipped {count}: the true pose is " + why,
                noun="message",
                first=f"{stamp / NS:.3f} s: {what}",
            )
            return
        current = self.offset @ _pose_transform(msg.pose.pose)
        try:
            odom_base = self.buffer.lookup_transform(self.odom_frame, self.base_frame, stamp)
        except TFError as err:
            logger.error(
                "%s: Failed to transform to %s from %s: %s",
                self.node.full_name,
                self.odom_frame,
                self.base_frame,
                err.message,
            )
            return
        map_odom = current @ odom_base.inverse()
        self.broadcaster.send(
            self.global_frame,
            self.odom_frame,
            map_odom.translation,
            map_odom.quat_xyzw,
            stamp + self.tolerance_ns,
        )
        pose = {
            "position": dict(zip("xyz", current.translation, strict=True)),
            "orientation": dict(zip("xyzw", current.quat_xyzw, strict=True)),
        }
        header = {
            "seq": int(msg.header.seq),
            "stamp": {"sec": stamp // NS, "nanosec": stamp % NS},
            "frame_id": self.global_frame,
        }
        self.pose_pub.publish_data({"header": header, "pose": {"pose": pose}})
        self.cloud_pub.publish_data({"header": header, "poses": [pose]})

    def _shift(self, msg: Any) -> None:
        problem = _pose_problem(msg.pose.pose)
        at = f"{stamp_ns(msg) / NS:.3f} s"
        template = "ignored {count}: it is "
        if self.tally.refused(problem, at=at, template=template, noun="initial pose"):
            return
        frame = str(msg.header.frame_id).lstrip("/")
        if frame != self.global_frame:
            logger.warning(
                '%s: Frame ID of "initialpose" (%s) is different from the global frame %s',
                self.node.full_name,
                msg.header.frame_id,
                self.global_frame,
            )
        try:
            base_in_map = self.buffer.lookup_transform(
                self.base_frame, self.global_frame, stamp_ns(msg)
            )
        except TFError:
            logger.warning("%s: Failed to lookup transform!", self.node.full_name)
            return
        delta = _pose_transform(msg.pose.pose) @ base_in_map
        self.offset = delta @ self.offset
        yaw = 2.0 * math.atan2(self.offset.quat_xyzw[2], self.offset.quat_xyzw[3])
        self.node.logger.info(
            "offset now (%.3f, %.3f, %.3f)",
            self.offset.translation[0],
            self.offset.translation[1],
            yaw,
        )


EXECUTABLES: dict[str, Starter] = {
    "fake_localization": stopping_on_bad_values(lambda session, spec, node: _FakeLocalization(node))
}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
TRANSFORMS: dict[str, TransformClaim] = {
    "fake_localization": frame_claim(PARAMETERS, "global_frame_id", "odom_frame_id")
}
