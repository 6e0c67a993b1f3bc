"""tf2_geometry_msgs (no oracle in Debian: it needs PyKDL): ``Buffer.transform`` of points,
vectors and poses agrees with tf's ``TransformerROS`` (checked against Debian's tf in
test_tf1.py) on the same buffer, up to the quaternion's sign."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from belvedere.ros1 import message_class, rospy, tf, tf2_geometry_msgs, tf2_ros

unit_quaternions = (
    st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4)
    .filter(lambda q: sum(c * c for c in q) > 0.01)
    .map(lambda q: [c / math.sqrt(sum(c * c for c in q)) for c in q])
)
vectors = st.lists(st.floats(-10.0, 10.0), min_size=3, max_size=3)


def _transformer(t: list[float], q: list[float]) -> tf.TransformerROS:
    transformer = tf.TransformerROS()
    msg: Any = message_class("geometry_msgs/TransformStamped")()
    msg.header.frame_id, msg.child_frame_id = "map", "base"
    msg.header.stamp = rospy.Time(5)
    tr, r = msg.transform.translation, msg.transform.rotation
    tr.x, tr.y, tr.z = t
    r.x, r.y, r.z, r.w = q
    transformer.setTransform(msg)
    return transformer


def _stamped(kind: str) -> Any:
    msg: Any = message_class(f"geometry_msgs/{kind}")()
    msg.header.frame_id = "base"
    msg.header.stamp = rospy.Time(5)
    return msg


@settings(max_examples=100)
@given(vectors, unit_quaternions, vectors, unit_quaternions)
def test_transform_agrees_with_tf(
    t: list[float], q: list[float], p: list[float], o: list[float]
) -> None:
    transformer = _transformer(t, q)
    buffer: tf2_ros.Buffer = transformer._buffer
    point = _stamped("PointStamped")
    point.point.x, point.point.y, point.point.z = p
    ours, theirs = buffer.transform(point, "map"), transformer.transformPoint("map", point)
    assert (ours.point.x, ours.point.y, ours.point.z) == pytest.approx(
        (theirs.point.x, theirs.point.y, theirs.point.z), abs=1e-9
    )
    assert ours.header.frame_id == "map"
    assert ours.header.stamp == rospy.Time(5)
    vector = _stamped("Vector3Stamped")
    vector.vector.x, vector.vector.y, vector.vector.z = p
    ours, theirs = buffer.transform(vector, "map"), transformer.transformVector3("map", vector)
    assert (ours.vector.x, ours.vector.y, ours.vector.z) == pytest.approx(
        (theirs.vector.x, theirs.vector.y, theirs.vector.z), abs=1e-9
    )
    pose = _stamped("PoseStamped")
    pos, ori = pose.pose.position, pose.pose.orientation
    pos.x, pos.y, pos.z = p
    ori.x, ori.y, ori.z, ori.w = o
    ours, theirs = buffer.transform(pose, "map"), transformer.transformPose("map", pose)
    a, b = ours.pose, theirs.pose
    assert (a.position.x, a.position.y, a.position.z) == pytest.approx(
        (b.position.x, b.position.y, b.position.z), abs=1e-9
    )
    qa = np.array([a.orientation.x, a.orientation.y, a.orientation.z, a.orientation.w])
    qb = np.array([b.orientation.x, b.orientation.y, b.orientation.z, b.orientation.w])
    assert min(np.abs(qa - qb).max(), np.abs(qa + qb).max()) < 1e-9
    covariant = _stamped("PoseWithCovarianceStamped")
    covariant.pose.pose = pose.pose
    covariant.pose.covariance = [float(i) for i in range(36)]
    moved = buffer.transform(covariant, "map")
    assert moved.pose.pose.position.x == pytest.approx(a.position.x, abs=1e-9)
    assert list(moved.pose.covariance) == [float(i) for i in range(36)]


def test_do_transform_vector3_leaves_the_transform_alone() -> None:
    transform: Any = message_class("geometry_msgs/TransformStamped")()
    transform.transform.translation.x = 2.0
    transform.transform.rotation.w = 1.0
    vector = _stamped("Vector3Stamped")
    vector.vector.x = 1.0
    assert tf2_geometry_msgs.do_transform_vector3(vector, transform).vector.x == 1.0
    assert transform.transform.translation.x == 2.0


def test_quaternion_sign_follows_kdl() -> None:
    """KDL's quaternion of a half turn about z: (0, 0, 1, 0), z positive."""
    transform: Any = message_class("geometry_msgs/TransformStamped")()
    transform.transform.rotation.z = -1.0  # the same half turn, written negated
    pose = _stamped("PoseStamped")
    pose.pose.orientation.w = 1.0
    o = tf2_geometry_msgs.do_transform_pose(pose, transform).pose.orientation
    assert (o.x, o.y, o.z, o.w) == (0.0, 0.0, 1.0, 0.0)
