"""The standard TF nodes: a listener, robot_state_publisher, joint_state_publisher and
static_transform_publisher, with the parameters and behaviour of their ROS 1 originals."""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence
from typing import Any

from belvedere.description.urdf import Joint, RobotModel
from belvedere.errors import BelvedereError
from belvedere.graph import Node
from belvedere.msgs import build
from belvedere.tf._buffer import TFBuffer
from belvedere.tf._math import Transform, quat_xyzw_from_rpy

__all__ = [
    "JointStatePublisher",
    "RobotStatePublisher",
    "TransformBroadcaster",
    "TransformListener",
    "parse_static_transform_args",
    "static_transform_publisher",
]


class TransformBroadcaster:
    """tf's TransformBroadcaster: transforms on ``/tf`` (built only when someone listens)."""

    def __init__(self, node: Node) -> None:
        self.pub = node.publisher("/tf", "tf2_msgs/TFMessage", queue_size=100)

    def send(
        self,
        parent: str,
        child: str,
        translation: build.Floats,
        quat_xyzw: build.Floats,
        stamp_ns: int,
    ) -> None:
        self.send_all([(parent, child, translation, quat_xyzw)], stamp_ns)

    def send_all(
        self,
        transforms: Sequence[tuple[str, str, build.Floats, build.Floats]],
        stamp_ns: int,
    ) -> None:
        """Several (parent, child, translation, quat_xyzw) in one message."""
        if self.pub.wanted:
            self.pub.publish(
                build.tf_message(
                    [build.transform_stamped(p, c, t, q, stamp_ns) for p, c, t, q in transforms]
                )
            )


class TransformListener:
    """Fills a :class:`TFBuffer` from ``/tf`` and ``/tf_static``."""

    def __init__(self, node: Node, buffer: TFBuffer | None = None) -> None:
        self.buffer = buffer or TFBuffer()
        node.subscribe("/tf", "tf2_msgs/TFMessage", self.buffer.set_message, queue_size=100)
        node.subscribe(
            "/tf_static",
            "tf2_msgs/TFMessage",
            lambda m: self.buffer.set_message(m, static=True),
            queue_size=100,
        )


class RobotStatePublisher:
    """``joint_states`` + the robot model → ``/tf`` (movable joints) and ``/tf_static``
    (fixed joints, latched, once). Parameters: ``~publish_frequency`` (50 Hz), ``~tf_prefix``;
    the model comes from the argument or the ``robot_description`` parameter."""

    def __init__(self, node: Node, model: RobotModel | None = None) -> None:
        self.node = node
        if model is None:
            text = node.get_param("robot_description", None)
            if text is None:
                msg = "robot_state_publisher: parameter robot_description is not set"
                raise BelvedereError(msg, hint="load the URDF into robot_description first")
            model = RobotModel.from_string(text, path="robot_description")
        self.model = model
        prefix = str(node.get_param("~tf_prefix", "")).strip("/")
        self.prefix = f"{prefix}/" if prefix else ""
        self.positions: dict[str, float] = {}
        self._cache: dict[str, tuple[float, Transform]] = {}
        self.tf_pub = node.publisher("/tf", "tf2_msgs/TFMessage", queue_size=100)
        self.static_pub = node.publisher("/tf_static", "tf2_msgs/TFMessage", latch=True)
        self.movable = [
            j for j in model.joints if j.type in ("revolute", "continuous", "prismatic")
        ]
        self._publish_static()
        node.subscribe(
            "joint_states", "sensor_msgs/JointState", self._on_joint_states, queue_size=10
        )
        freq = float(node.get_param("~publish_frequency", 50.0))
        if freq <= 0:
            msg = f"robot_state_publisher: publish_frequency must be positive, got {freq}"
            raise BelvedereError(msg)
        node.timer(1.0 / freq, self.publish)

    def _transform(self, joint: Joint, q: float) -> Transform:
        return Transform.from_matrix(self.model.joint_transform(joint, q))

    def frame(self, link: str) -> str:
        return self.prefix + link

    def _publish_static(self) -> None:
        stamp = self.node.now_ns()
        fixed = [
            self._stamped(j, self._transform(j, 0.0), stamp)
            for j in self.model.joints
            if j.type == "fixed"
        ]
        if fixed:
            self.static_pub.publish(build.tf_message(fixed))

    def _stamped(self, joint: Joint, t: Transform, stamp: int) -> Any:
        return build.transform_stamped(
            self.frame(joint.parent), self.frame(joint.child), t.translation, t.quat_xyzw, stamp
        )

    def _on_joint_states(self, msg: Any) -> None:
        for name, value in zip(msg.name, msg.position, strict=False):
            self.positions[name] = float(value)

    def _cached_transform(self, joint: Joint, q: float) -> Transform:
        # Joints mostly sit still between publications: recompute only when one moves.
        cached = self._cache.get(joint.name)
        if cached is not None and cached[0] == q:
            return cached[1]
        t = self._transform(joint, q)
        self._cache[joint.name] = (q, t)
        return t

    def publish(self) -> None:
        if not self.tf_pub.wanted:
            return
        stamp = self.node.now_ns()
        positions = self.positions
        transforms = [
            self._stamped(j, self._cached_transform(j, positions[j.name]), stamp)
            for j in self.movable
            if j.name in positions
        ]
        if transforms:
            self.tf_pub.publish(build.tf_message(transforms))


class JointStatePublisher:
    """Publishes ``joint_states`` for the movable joints: ``~rate`` (10 Hz), ``~zeros``
    (initial positions), ``~source_list`` (topics whose joint states override), mimic joints
    following their leaders. A joint whose limits exclude 0 starts at their middle.
    ``exclude`` (ours) leaves out joints another node reports, e.g. a driver's servos."""

    def __init__(
        self,
        node: Node,
        model: RobotModel | None = None,
        *,
        exclude: Collection[str] = (),
    ) -> None:
        self.node = node
        if model is None:
            text = node.get_param("robot_description", None)
            if text is None:
                msg = "joint_state_publisher: parameter robot_description is not set"
                raise BelvedereError(msg)
            model = RobotModel.from_string(text, path="robot_description")
        self.model = model
        self.free = [
            j
            for j in model.joints
            if j.type in ("revolute", "continuous", "prismatic")
            and j.mimic is None
            and j.name not in exclude
        ]
        self.mimics = [
            j
            for j in model.joints
            if j.mimic is not None and j.type != "fixed" and j.mimic.joint not in exclude
        ]
        zeros = node.get_param("~zeros", {}) or {}
        self.positions: dict[str, float] = {}
        for j in self.free:
            default = 0.0
            if (
                j.limit is not None
                and j.type != "continuous"
                and not j.limit.lower <= 0.0 <= j.limit.upper
            ):
                default = (j.limit.lower + j.limit.upper) / 2
            self.positions[j.name] = float(zeros.get(j.name, default))
        for topic in node.get_param("~source_list", []) or []:
            node.subscribe(topic, "sensor_msgs/JointState", self._on_source, queue_size=10)
        self.pub = node.publisher("joint_states", "sensor_msgs/JointState", queue_size=10)
        rate = float(node.get_param("~rate", 10.0))
        node.timer(1.0 / rate, self.publish)

    def set_position(self, joint: str, value: float) -> None:
        if joint not in self.positions:
            msg = f"joint_state_publisher: {joint!r} is not a free movable joint"
            raise BelvedereError(msg)
        self.positions[joint] = value

    def _on_source(self, msg: Any) -> None:
        for name, value in zip(msg.name, msg.position, strict=False):
            if name in self.positions:
                self.positions[name] = float(value)

    def current(self) -> dict[str, float]:
        out = dict(self.positions)
        for j in self.mimics:
            assert j.mimic is not None
            leader = out.get(j.mimic.joint, 0.0)
            out[j.name] = j.mimic.multiplier * leader + j.mimic.offset
        return out

    def publish(self) -> None:
        if not self.pub.wanted:
            return
        values = self.current()
        names = [j.name for j in self.model.joints if j.name in values]
        zeros = [0.0] * len(names)
        self.pub.publish(
            build.joint_state(self.node.now_ns(), names, [values[n] for n in names], zeros, zeros)
        )


def parse_static_transform_args(args: Sequence[str]) -> tuple[str, str, Transform]:
    """Both argument forms: ``x y z yaw pitch roll frame child [period_ms]`` and
    ``x y z qx qy qz qw frame child [period_ms]`` (the period is tf's, ignored: static)."""
    words = list(args)
    usage = (
        "static_transform_publisher x y z yaw pitch roll frame_id child_frame_id [period_ms] "
        "or x y z qx qy qz qw frame_id child_frame_id [period_ms]"
    )

    def numbers(items: list[str]) -> list[float]:
        try:
            return [float(v) for v in items]
        except ValueError:
            msg = f"expected numbers, got {' '.join(items)!r}; usage: {usage}"
            raise BelvedereError(msg) from None

    if len(words) in (8, 9) and _is_number(words[5]) and not _is_number(words[6]):
        x, y, z, yaw, pitch, roll = numbers(words[:6])
        return words[6], words[7], Transform((x, y, z), quat_xyzw_from_rpy(roll, pitch, yaw))
    if len(words) in (9, 10):
        x, y, z, qx, qy, qz, qw = numbers(words[:7])
        n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
        if n == 0:
            msg = "quaternion of the static transform is zero"
            raise BelvedereError(msg)
        return words[7], words[8], Transform((x, y, z), (qx / n, qy / n, qz / n, qw / n))
    msg = f"wrong number of arguments ({len(words)}); usage: {usage}"
    raise BelvedereError(msg)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def static_transform_publisher(node: Node, args: Sequence[str]) -> None:
    """Publish one static transform on ``/tf_static`` (latched)."""
    parent, child, transform = parse_static_transform_args(args)
    pub = node.publisher("/tf_static", "tf2_msgs/TFMessage", latch=True)
    stamped = build.transform_stamped(
        parent, child, transform.translation, transform.quat_xyzw, node.now_ns()
    )
    pub.publish(build.tf_message([stamped]))
