#!/usr/bin/env python3
"""Prints the fields of every /cmd_vel command until the stop (all zeros)."""

import rospy
from geometry_msgs.msg import Twist

count = 0


def on_cmd(msg):
    global count
    count += 1
    if count == 1:
        print(msg)
        print(repr(msg.linear))
    print("#%d linear.x=%.2f angular.z=%+.1f" % (count, msg.linear.x, msg.angular.z))
    if count > 1 and msg == Twist():
        rospy.logwarn("stopped after %d commands", count)
        rospy.signal_shutdown("stop received")


rospy.init_node("cmd_listener")
rospy.Subscriber("/cmd_vel", Twist, on_cmd, queue_size=20)
rospy.Timer(rospy.Duration(10), lambda event: rospy.signal_shutdown("timeout"), oneshot=True)
rospy.spin()
