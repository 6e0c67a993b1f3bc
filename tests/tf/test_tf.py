"""TF: transform math, the buffer, and the standard TF nodes."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from belvedere.description.urdf import RobotModel, rpy_to_matrix
from belvedere.errors import BelvedereError
from belvedere.graph import NS, Graph
from belvedere.msgs import build
from belvedere.tf import (
    JointStatePublisher,
    RobotStatePublisher,
    TFBuffer,
    TFError,
    Transform,
    TransformListener,
    parse_static_transform_args,
    quat_xyzw_from_rpy,
    quat_xyzw_to_matrix,
    rpy_from_quat_xyzw,
    static_transform_publisher,
    wxyz_from_xyzw,
    xyzw_from_wxyz,
)
from tests.conftest import DATA, EXAMPLES

angles = st.floats(-math.pi, math.pi)
coords = st.floats(-100, 100)
transforms = st.builds(
    lambda x, y, z, r, p, yw: Transform((x, y, z), quat_xyzw_from_rpy(r, p, yw)),
    coords,
    coords,
    coords,
    angles,
    angles,
    angles,
)


@given(angles, angles, angles)
def test_rpy_quaternion_matches_urdf_convention(r: float, p: float, y: float) -> None:
    assert quat_xyzw_to_matrix(quat_xyzw_from_rpy(r, p, y)) == pytest.approx(
        rpy_to_matrix((r, p, y)), abs=1e-9
    )


def test_quaternion_orders_are_explicit() -> None:
    q = quat_xyzw_from_rpy(0, 0, math.pi / 2)
    assert wxyz_from_xyzw(q)[0] == pytest.approx(math.cos(math.pi / 4))
    assert xyzw_from_wxyz(wxyz_from_xyzw(q)) == q
    assert rpy_from_quat_xyzw(q) == pytest.approx((0, 0, math.pi / 2))


@settings(max_examples=100)
@given(transforms, transforms, transforms)
def test_group_axioms(a: Transform, b: Transform, c: Transform) -> None:
    assert ((a @ b) @ c).matrix() == pytest.approx((a @ (b @ c)).matrix(), abs=1e-6)
    assert (a @ a.inverse()).matrix() == pytest.approx(np.eye(4), abs=1e-6)
    assert (a @ b).matrix() == pytest.approx(a.matrix() @ b.matrix(), abs=1e-6)
    assert Transform.from_matrix(a.matrix()).matrix() == pytest.approx(a.matrix(), abs=1e-6)


def test_set_transform_logs_a_refused_one_and_keeps_the_first() -> None:
    """tf2 ignores a second transform at the same stamp with a warning (it recursed here)."""
    logged: list[tuple[str, str]] = []
    buf = TFBuffer(log=lambda level, text: logged.append((level, text)))
    buf.set_transform("odom", "base", Transform((1, 0, 0)), 1_000_000_000)
    buf.set_transform("odom", "base", Transform((2, 0, 0)), 1_000_000_000)
    assert [level for level, _ in logged] == ["Warning"]
    assert "for frame base at time 1.000000" in logged[0][1]
    assert buf.lookup_transform("odom", "base").translation == pytest.approx((1, 0, 0))


def test_buffer_lookup_interpolation_and_errors() -> None:
    buf = TFBuffer()
    buf.set_transform("map", "odom", Transform((1, 0, 0)), 0, static=True)
    buf.set_transform("odom", "base", Transform((0, 0, 0)), 1_000_000_000)
    buf.set_transform("odom", "base", Transform((2, 0, 0)), 2_000_000_000)
    buf.set_transform("base", "laser", Transform((0, 0, 0.5)), 0, static=True)
    t = buf.lookup_transform("map", "laser", 1_500_000_000)
    assert t.translation == pytest.approx((2, 0, 0.5))
    assert buf.lookup_transform("map", "laser").translation == pytest.approx((3, 0, 0.5))
    assert buf.lookup_transform("laser", "map").translation == pytest.approx((-3, 0, -0.5))
    with pytest.raises(TFError, match=r"extrapolation 1\.000000000s into the future\.") as err:
        buf.lookup_transform("map", "base", 3_000_000_000)
    assert err.value.message.endswith(
        "the latest data is at time 2.000000000, when looking up transform from frame [base] "
        "to frame [map]"
    )
    with pytest.raises(TFError, match='"nowhere" passed to lookupTransform') as err:
        buf.lookup_transform("map", "nowhere")
    assert err.value.hint == "the frames known: base, laser, map, odom"
    buf.set_transform("world", "other", Transform(), 0, static=True)
    with pytest.raises(
        TFError,
        match="Could not find a connection between 'map' and 'other' because they are not part "
        "of the same tree",
    ):
        buf.lookup_transform("map", "other")
    with pytest.raises(TFError, match="TF_SELF_TRANSFORM"):
        buf.set_transform("map", "/map", Transform(), 0)
    assert "base [" in buf.tree()


def test_robot_state_publisher_matches_forward_kinematics() -> None:
    model = RobotModel.from_path(DATA / "urdf" / "check" / "valid_full.urdf")
    g = Graph()
    g.params.set("/robot_description", model.to_urdf())
    RobotStatePublisher(g.create_node("robot_state_publisher"))
    jsp = JointStatePublisher(g.create_node("joint_state_publisher"))
    listener = TransformListener(g.create_node("listener"))
    q = {"shoulder": 0.4, "wrist": -1.2, "finger_a_joint": 0.3}
    for name, value in q.items():
        jsp.set_position(name, value)
    g.run(duration=0.5)
    fk = model.forward_kinematics(q)
    for link in ("arm", "hand", "finger_a", "finger_b", "slider"):
        t = listener.buffer.lookup_transform("base", link)
        assert t.matrix() == pytest.approx(fk[link], abs=1e-9), link
    # mimic: finger_b follows finger_a with multiplier -1
    assert jsp.current()["finger_b_joint"] == pytest.approx(-0.3)


def test_joint_state_publisher_defaults_and_zeros() -> None:
    model = RobotModel.from_string(
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="j1" type="revolute"><parent link="a"/><child link="b"/>'
        '<limit lower="0.5" upper="1.5" effort="1" velocity="1"/></joint>'
        '<joint name="j2" type="continuous"><parent link="b"/><child link="c"/></joint></robot>'
    )
    g = Graph()
    node = g.create_node("jsp", params={"zeros": {"j2": 0.7}})
    jsp = JointStatePublisher(node, model)
    assert jsp.current() == {"j1": 1.0, "j2": 0.7}  # 0 is outside j1's limits: its middle


def test_tf_prefix_and_mbot_example() -> None:
    model = RobotModel.from_path(
        EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"
    )
    g = Graph()
    node = g.create_node("robot_state_publisher", params={"tf_prefix": "robot1"})
    RobotStatePublisher(node, model)
    JointStatePublisher(g.create_node("joint_state_publisher"), model)
    listener = TransformListener(g.create_node("listener"))
    g.run(duration=0.2)
    t = listener.buffer.lookup_transform("robot1/base_footprint", "robot1/base_link")
    assert t.translation == pytest.approx((0, 0, 0.11))
    with pytest.raises(BelvedereError, match="robot_description is not set"):
        RobotStatePublisher(g.create_node("rsp2"))


@pytest.mark.parametrize(
    "args",
    [
        ["1", "2", "3", str(math.pi / 2), "0", "0", "map", "odom"],
        ["1", "2", "3", str(math.pi / 2), "0", "0", "map", "odom", "100"],
        [
            "1",
            "2",
            "3",
            "0",
            "0",
            str(math.sin(math.pi / 4)),
            str(math.cos(math.pi / 4)),
            "map",
            "odom",
        ],
    ],
)
def test_static_transform_argument_forms(args: list[str]) -> None:
    parent, child, t = parse_static_transform_args(args)
    assert (parent, child) == ("map", "odom")
    assert t.translation == (1, 2, 3)
    assert rpy_from_quat_xyzw(t.quat_xyzw) == pytest.approx((0, 0, math.pi / 2))  # yaw first


def test_static_transform_publisher_and_bad_args() -> None:
    g = Graph()
    static_transform_publisher(g.create_node("stp"), ["0", "0", "1", "0", "0", "0", "base", "cam"])
    listener = TransformListener(g.create_node("listener"))
    g.spin_once()
    assert listener.buffer.lookup_transform("base", "cam").translation == (0, 0, 1)
    with pytest.raises(BelvedereError, match="wrong number of arguments"):
        parse_static_transform_args(["1", "2"])


RSP_MODEL = (
    '<robot name="r"><link name="base"/><link name="a"/><link name="b"/><link name="c"/>'
    '<joint name="lead" type="continuous"><parent link="base"/><child link="a"/>'
    '<axis xyz="0 0 1"/></joint>'
    '<joint name="slide" type="prismatic"><parent link="a"/><child link="b"/>'
    '<axis xyz="0 0 2"/><limit lower="-9" upper="9" effort="1" velocity="1"/>'
    '<mimic joint="lead" multiplier="2" offset="0.5"/></joint>'
    '<joint name="tip" type="fixed"><parent link="b"/><child link="c"/>'
    '<origin xyz="1 0 0"/></joint></robot>'
)


def test_robot_state_publisher_publishes_each_message_with_its_stamp() -> None:
    g = Graph(clock_hz=None)
    node = g.create_node("robot_state_publisher", params={"publish_frequency": 10.0})
    RobotStatePublisher(node, RobotModel.from_string(RSP_MODEL))
    tf: list[Any] = []
    static: list[Any] = []
    listener = g.create_node("listener")
    listener.subscribe("/tf", "tf2_msgs/TFMessage", tf.append, queue_size=100)
    listener.subscribe("/tf_static", "tf2_msgs/TFMessage", static.append, queue_size=100)
    states = listener.publisher("joint_states", "sensor_msgs/JointState")
    g.run(duration=0.05)
    assert not static  # one-shot, 1/publish_frequency after the start
    g.run(duration=0.1)
    assert len(static) == 1
    (fixed,) = static[0].transforms
    assert (fixed.header.frame_id, fixed.child_frame_id) == ("b", "c")
    assert fixed.header.stamp.nanosec == 100_000_000
    g.run(duration=6.0)  # past the stamps: "now" bounds the throttle too, as in ROS
    assert not tf  # nothing without joint_states, however long
    for stamp_ns in (5 * NS, 5 * NS + 50_000_000, 5 * NS + 100_000_000):
        states.publish(build.joint_state(stamp_ns, ["lead"], [0.25]))
        g.spin_once()
    assert [
        m.transforms[0].header.stamp.sec * NS + m.transforms[0].header.stamp.nanosec for m in tf
    ] == [5 * NS, 5 * NS + 100_000_000]  # the second within 0.1 s: left out
    lead, slide = tf[0].transforms
    assert (lead.child_frame_id, slide.child_frame_id) == ("a", "b")
    # the mimic follows at 2 * 0.25 + 0.5 = 1 along the axis made unit length
    assert (slide.transform.translation.x, slide.transform.translation.z) == (0.0, 1.0)
    assert lead.transform.rotation.z == pytest.approx(math.sin(0.125))


def test_publishers_number_header_seq_as_ros1() -> None:
    g = Graph(clock_hz=None)
    a, b = g.create_node("a"), g.create_node("b")
    got: list[tuple[str, int]] = []
    cpp = a.publisher("/js", "sensor_msgs/JointState")
    cpp.publish(build.joint_state(0, [], []))  # roscpp counts messages nobody hears
    py = b.publisher("/js", "sensor_msgs/JointState", seq_rule="rospy")
    py.publish(build.joint_state(0, [], []))  # rospy does not
    a.subscribe("/js", "sensor_msgs/JointState", lambda m: got.append(("msg", m.header.seq)))
    sent = build.joint_state(0, [], [])
    for _ in range(2):
        cpp.publish(sent)
        py.publish(sent)
    g.spin_once()
    assert got == [("msg", 1), ("msg", 1), ("msg", 2), ("msg", 2)]
    assert sent.header.seq == 0  # the caller's message is left alone
    # a second publisher of the same node on the same topic shares the count
    a.publisher("/js", "sensor_msgs/JointState").publish(build.joint_state(0, [], []))
    g.spin_once()
    assert got[-1] == ("msg", 3)


def test_a_message_built_with_next_seq_is_sent_as_it_is() -> None:
    """What the simulation's 100 Hz publishers do to spare the numbering copy."""
    g = Graph(clock_hz=None)
    node = g.create_node("a")
    got: list[object] = []
    node.subscribe("/odom", "nav_msgs/Odometry", got.append, queue_size=0)
    for rule in ("roscpp", "rospy"):
        pub = node.publisher("/odom", "nav_msgs/Odometry", seq_rule=rule)
        for _ in range(3):
            seq = pub.next_seq()
            msg = build.odometry(
                stamp_ns=0,
                frame_id="odom",
                child_frame_id="base",
                position=(0, 0, 0),
                quat_xyzw=(0, 0, 0, 1),
                seq=seq,
            )
            pub.publish(msg)
            g.spin_once()
            assert got[-1] is msg
    assert [m.header.seq for m in got] == [0, 1, 2, 4, 5, 6]  # type: ignore[attr-defined]
