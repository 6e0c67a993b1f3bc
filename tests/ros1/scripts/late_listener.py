#!/usr/bin/env python3
"""Subscribes after the latched message was published: it still gets it."""

import rospy
from std_msgs.msg import String

got = []


def on_map(msg):
    rospy.loginfo("late joiner got: %s", msg.data)
    got.append(msg.data)


rospy.init_node("late_listener")
rospy.Subscriber("/map_name", String, on_map)
deadline = rospy.get_time() + 10
while not got and rospy.get_time() < deadline:
    rospy.sleep(0.01)
rospy.sleep(0.5)  # linger, so the publisher sees us connected
print("late listener done:", got)
