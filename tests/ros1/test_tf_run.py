"""tf and tf2_ros end to end: a rospy script run by ``belvedere run`` looks up the transforms
that belvedere's robot_state_publisher and a static_transform_publisher, run by ``belvedere
launch`` in another process, publish; and broadcasts its own."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

BELVEDERE = [sys.executable, "-m", "belvedere"]
DEADLINE = 120

URDF = """\
<robot name="r">
  <link name="base_link"/><link name="torso"/><link name="arm"/>
  <joint name="torso_joint" type="fixed">
    <parent link="base_link"/><child link="torso"/><origin xyz="0 0 0.1"/>
  </joint>
  <joint name="arm_joint" type="continuous">
    <parent link="torso"/><child link="arm"/><origin xyz="0.2 0 0"/><axis xyz="0 0 1"/>
  </joint>
</robot>
"""

LAUNCH = """\
<launch>
  <param name="robot_description" textfile="$(dirname)/r.urdf"/>
  <node pkg="robot_state_publisher" type="robot_state_publisher" name="rsp"/>
  <node pkg="joint_state_publisher" type="joint_state_publisher" name="jsp">
    <rosparam param="zeros">{arm_joint: 0.5}</rosparam>
  </node>
  <node pkg="tf2_ros" type="static_transform_publisher" name="cam"
        args="0.1 0 0.2 0 0 0 base_link camera"/>
</launch>
"""

SCRIPT = """\
import re

import rospy
import tf
import tf2_ros
import tf2_geometry_msgs
import tf_conversions
from geometry_msgs.msg import PointStamped, TransformStamped
from tf.transformations import quaternion_from_euler
from tf2_ros.buffer import Buffer

assert Buffer is tf2_ros.Buffer
print(tf_conversions.transformations.euler_from_quaternion(quaternion_from_euler(0.1, 0, 0)))

rospy.init_node("tf_check")
buf = tf2_ros.Buffer()
listener = tf2_ros.TransformListener(buf)

t = buf.lookup_transform("base_link", "camera", rospy.Time(0), rospy.Duration(20))
print("camera", t.header.frame_id, t.child_frame_id, t.transform.translation.x,
      t.transform.translation.z, t.transform.rotation.w)
t = buf.lookup_transform("base_link", "arm", rospy.Time(0), rospy.Duration(20))
x, y, z = t.transform.translation.x, t.transform.translation.y, t.transform.translation.z
yaw = tf.transformations.euler_from_quaternion(
    [t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
     t.transform.rotation.w])[2]
print("arm %.3f %.3f %.3f yaw %.3f" % (x, y, z, yaw))

p = PointStamped()
p.header.frame_id = "camera"
p.point.x = 1.0
q = buf.transform(p, "arm")
print("point in %s: %.3f %.3f %.3f" % (q.header.frame_id, q.point.x, q.point.y, q.point.z))

try:
    buf.lookup_transform("base_link", "nowhere", rospy.Time(0), rospy.Duration(0.2))
except tf2_ros.LookupException as e:
    print("LookupException:", e)
try:
    buf.lookup_transform("base_link", "arm", rospy.Time.now() + rospy.Duration(100))
except tf2_ros.ExtrapolationException as e:
    print("ExtrapolationException:", re.sub(r"\\d+\\.\\d+", "N", str(e)))

old = tf.TransformListener()
old.waitForTransform("/base_link", "/arm", rospy.Time(0), rospy.Duration(20))
trans, rot = old.lookupTransform("/base_link", "/arm", rospy.Time(0))
print("tf1 arm", ["%.3f" % v for v in trans])
try:
    old.waitForTransform("base_link", "nowhere", rospy.Time(0), rospy.Duration(0.3))
except tf.Exception as e:
    print("tf.Exception:", e)

static = tf2_ros.StaticTransformBroadcaster()
tool = TransformStamped()
tool.header.stamp = rospy.Time.now()
tool.header.frame_id = "arm"
tool.child_frame_id = "tool"
tool.transform.translation.x = 0.3
tool.transform.rotation.w = 1.0
static.sendTransform(tool)
tf.TransformBroadcaster().sendTransform(
    (0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 1.0), rospy.Time.now(), "marker", "base_link")
t = buf.lookup_transform("camera", "tool", rospy.Time(0), rospy.Duration(20))
print("tool in camera %.3f %.3f %.3f" % (
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z))
old.waitForTransform("marker", "base_link", rospy.Time(0), rospy.Duration(20))
print("marker", old.lookupTransform("marker", "base_link", rospy.Time(0))[0])
"""


def test_a_script_looks_up_what_other_processes_publish(tmp_path: Path) -> None:
    (tmp_path / "r.urdf").write_text(URDF)
    launch = tmp_path / "robot.launch"
    launch.write_text(LAUNCH)
    script = tmp_path / "check.py"
    script.write_text(textwrap.dedent(SCRIPT))
    host = subprocess.Popen(
        [*BELVEDERE, "launch", str(launch), "--headless"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert host.stderr is not None
        line = host.stderr.readline()
        while line and "listening" not in line:  # after roslaunch's summary
            line = host.stderr.readline()
        assert "listening" in line  # the graph is up
        done = subprocess.run(
            [*BELVEDERE, "run", str(script)],
            capture_output=True,
            text=True,
            timeout=DEADLINE,
            check=False,
        )
    finally:
        host.terminate()
        host.wait(timeout=DEADLINE)
    assert done.returncode == 0, done.stderr
    yaw = 0.5
    import math

    cx, cy = 0.2 + 0.0, 0.0  # the arm's origin in base_link (x, y)
    # camera (0.1, 0, 0.2 in base_link) + 1 m along x, seen from the arm
    dx, dy = 0.1 + 1.0 - cx, 0.0 - cy
    in_arm = (
        math.cos(yaw) * dx + math.sin(yaw) * dy,
        -math.sin(yaw) * dx + math.cos(yaw) * dy,
        0.2 - 0.1,
    )
    tool = (0.2 + 0.3 * math.cos(yaw) - 0.1, 0.3 * math.sin(yaw), 0.1 - 0.2)
    assert done.stdout.splitlines() == [
        "(0.10000000000000002, -0.0, 0.0)",  # to the last digit as tf prints it
        "camera base_link camera 0.1 0.2 1.0",
        "arm 0.200 0.000 0.100 yaw 0.500",
        "point in arm: " + " ".join(f"{v:.3f}" for v in in_arm),
        'LookupException: "nowhere" passed to lookupTransform argument source_frame does not '
        "exist. ",
        "ExtrapolationException: Lookup would require extrapolation Ns into the future.  "
        "Requested time N but the latest data is at time N, when looking up transform from "
        "frame [arm] to frame [base_link]",
        "tf1 arm ['0.200', '0.000', '0.100']",
        "tf.Exception: canTransform: source_frame nowhere does not exist.",
        "tool in camera " + " ".join(f"{v:.3f}" for v in tool),
        "marker [0.0, -1.0, 0.0]",
    ]
