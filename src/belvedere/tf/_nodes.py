"""The standard TF nodes: a listener, robot_state_publisher, joint_state_publisher and
static_transform_publisher, with the parameters and behaviour of their ROS 1 originals."""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence
from typing import Any

from belvedere.description.urdf import Joint, RobotModel
from belvedere.errors import BelvedereError
from belvedere.graph import NS, Node
from belvedere.msgs import build
from belvedere.tf._buffer import TFBuffer
from belvedere.tf._math import Transform, quat_xyzw_from_rpy

__all__ = [
    "JointStatePublisher",
    "RobotStatePublisher",
    "TransformBroadcaster",
    "TransformListener",
    "parse_static_transform_args",
    "resolve_tf",
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
    """ROS 1's robot_state_publisher (1.15): ``joint_states`` + the robot model → ``/tf``
    and ``/tf_static``.

    As the original does:

    - each ``joint_states`` message is published at once, stamped with its own stamp, with a
      transform for each of its joints in the model (and each mimic joint whose leader it
      carries: ``multiplier * leader + offset``, unless the message names the follower
      too), ordered by joint name; a message is left out when all its joints were published
      less than ``1 / ~publish_frequency`` (50 Hz, at least 1 Hz) before its stamp, unless
      ``~ignore_timestamp``; one whose names and positions differ in number is refused;
    - the fixed joints (and planar ones, which KDL holds fixed) go once on ``/tf_static``
      (latched), ``1 / ~publish_frequency`` after the start, stamped with that time; with
      ``~use_tf_static`` false they go on ``/tf`` at that rate instead, stamped half a second
      ahead; floating joints are never published;
    - frames are resolved against ``tf_prefix``, searched from the node's private namespace
      up, as tf::resolve does.

    The model comes from the argument or the ``robot_description`` parameter."""

    def __init__(self, node: Node, model: RobotModel | None = None) -> None:
        self.node = node
        if model is None:
            text = node.get_param("robot_description", None)
            if text is None:
                msg = "robot_state_publisher: parameter robot_description is not set"
                raise BelvedereError(msg, hint="load the URDF into robot_description first")
            model = RobotModel.from_string(text, path="robot_description")
        self.model = model
        self.prefix = str(_search_param(node, "tf_prefix", ""))
        freq = float(node.get_param("~publish_frequency", 50.0))
        self.use_tf_static = bool(node.get_param("~use_tf_static", True))
        self.ignore_timestamp = bool(node.get_param("~ignore_timestamp", False))
        self.interval_ns = round(NS / max(freq, 1.0))
        self.segments = {j.name: j for j in model.joints if j.type in _MOVING}
        self.fixed = sorted(
            (j for j in model.joints if j.type not in _MOVING and j.type != "floating"),
            key=lambda j: j.name,
        )
        self.mimic = sorted((j.name, j.mimic) for j in model.joints if j.mimic is not None)
        self.last_publish_ns: dict[str, int] = {}
        self.last_callback_ns = 0
        self._cache: dict[str, tuple[float, Transform]] = {}
        self._said: set[str] = set()
        self.tf_pub = node.publisher("/tf", "tf2_msgs/TFMessage", queue_size=100)
        self.static_pub = node.publisher("/tf_static", "tf2_msgs/TFMessage", latch=True)
        node.subscribe("joint_states", "sensor_msgs/JointState", self.on_joint_states, queue_size=1)
        node.timer(self.interval_ns / NS, self.publish_fixed, oneshot=self.use_tf_static)

    def frame(self, link: str) -> str:
        """tf::resolve: ``prefix/link``; a leading slash on the link keeps it unprefixed."""
        return _resolve_frame(self.prefix, link)

    def publish_fixed(self) -> None:
        """The fixed joints' transforms, stamped now (half a second ahead on ``/tf``)."""
        stamp = self.node.now_ns()
        pub = self.static_pub
        if not self.use_tf_static:
            stamp += NS // 2
            pub = self.tf_pub
        pub.publish(
            build.tf_message([self._stamped(j, self._transform(j, 0.0), stamp) for j in self.fixed])
        )

    def on_joint_states(self, msg: Any) -> None:
        names, positions = list(msg.name), list(msg.position)
        if len(names) != len(positions):
            if not positions:
                self._warn_once(
                    "empty",
                    "Robot state publisher ignored a JointState message about joint(s) "
                    f'"{names[0]}"(,...) whose position member was empty.',
                )
            else:
                self.node.logger.error(
                    "Robot state publisher ignored an invalid JointState message"
                )
            return
        now = self.node.now_ns()
        if self.last_callback_ns > now:
            self.node.logger.warning(
                "Moved backwards in time (probably because ROS clock was reset), "
                "re-publishing joint transforms!"
            )
            self.last_publish_ns.clear()
        self.last_callback_ns = now
        stamp = msg.header.stamp.sec * NS + msg.header.stamp.nanosec
        last_published = now
        for name in names:
            last_published = min(last_published, self.last_publish_ns.get(name, 0))
        if not (self.ignore_timestamp or stamp >= last_published + self.interval_ns):
            return
        values: dict[str, float] = {}
        for name, value in zip(names, positions, strict=True):
            values.setdefault(name, float(value))  # std::map::insert keeps the first
        for follower, mimic in self.mimic:
            if mimic.joint in values:
                values.setdefault(follower, values[mimic.joint] * mimic.multiplier + mimic.offset)
        transforms = []
        for name in sorted(values):
            joint = self.segments.get(name)
            if joint is None:
                self._warn_once(
                    f"unknown {name}",
                    f'Joint state with name: "{name}" was received but not found in URDF',
                )
                continue
            transforms.append(
                self._stamped(joint, self._cached_transform(joint, values[name]), stamp)
            )
        self.tf_pub.publish(build.tf_message(transforms))
        for name in names:
            self.last_publish_ns[name] = stamp

    def _warn_once(self, key: str, text: str) -> None:
        # The original throttles these (to one per 10 s, 300 s); here once per node.
        if key not in self._said:
            self._said.add(key)
            self.node.logger.warning(text)

    def _transform(self, joint: Joint, q: float) -> Transform:
        return Transform.from_matrix(self.model.joint_transform(joint, q))

    def _stamped(self, joint: Joint, t: Transform, stamp: int) -> Any:
        return build.transform_stamped(
            self.frame(joint.parent), self.frame(joint.child), t.translation, t.quat_xyzw, stamp
        )

    def _cached_transform(self, joint: Joint, q: float) -> Transform:
        # Joints mostly sit still between messages: recompute only when one moves.
        cached = self._cache.get(joint.name)
        if cached is not None and cached[0] == q:
            return cached[1]
        t = self._transform(joint, q)
        self._cache[joint.name] = (q, t)
        return t


_MOVING = ("revolute", "continuous", "prismatic")


def _search_param(node: Node, key: str, default: Any) -> Any:
    """ROS's searchParam from the node's private namespace: the closest ``key`` upward."""
    parts = [p for p in node.full_name.split("/") if p]
    while True:
        name = "/" + "/".join([*parts, key])
        if node.graph.params.has(name):
            return node.graph.params.get(name)
        if not parts:
            return default
        parts.pop()


def resolve_tf(node: Node, frame: str) -> str:
    """tf::resolve(tf::getPrefixParam(node), frame): a Gazebo plugin's frame names, with the
    ``tf_prefix`` searched up from the node (a multi-robot launch's ``<group ns>``)."""
    return _resolve_frame(str(_search_param(node, "tf_prefix", "")), frame)


def _resolve_frame(prefix: str, frame: str) -> str:
    if frame.startswith("/"):
        return frame[1:]
    if prefix:
        return f"{prefix.removeprefix('/')}/{frame}"
    return frame


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
            bounds = j.position_range
            if bounds is not None and not bounds[0] <= 0.0 <= bounds[1]:
                default = (bounds[0] + bounds[1]) / 2
            self.positions[j.name] = float(zeros.get(j.name, default))
        for topic in node.get_param("~source_list", []) or []:
            node.subscribe(topic, "sensor_msgs/JointState", self._on_source, queue_size=10)
        # joint_state_publisher is a rospy node: its header.seq counts from 1
        self.pub = node.publisher(
            "joint_states", "sensor_msgs/JointState", queue_size=10, seq_rule="rospy"
        )
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
