#!/usr/bin/env python3
"""Prints the header of every PoseStamped it gets; ends after four."""

import rospy
from geometry_msgs.msg import PoseStamped

got = []


def on_pose(msg):
    got.append(msg)
    print(
        "seq",
        msg.header.seq,
        "frame",
        msg.header.frame_id,
        "x",
        msg.pose.position.x,
        "stamp zero:",
        msg.header.stamp.is_zero(),
    )
    if len(got) == 4:
        rospy.signal_shutdown("four poses")


rospy.init_node("header_sub")
rospy.Subscriber("/pose", PoseStamped, on_pose)
rospy.Timer(rospy.Duration(10), lambda event: rospy.signal_shutdown("timeout"), oneshot=True)
rospy.spin()
