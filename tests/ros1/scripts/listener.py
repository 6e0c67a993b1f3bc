#!/usr/bin/env python3
"""The ROS tutorial listener (anonymous), ending by itself after five messages."""

import rospy
from std_msgs.msg import String

received = []


def callback(data):
    received.append(data.data)
    rospy.loginfo("I heard %s", data.data)
    print("count", len(received), type(data).__name__, data._type)
    if len(received) == 5:
        rospy.signal_shutdown("got 5 messages")


def listener():
    rospy.init_node("listener", anonymous=True)
    sub = rospy.Subscriber("chatter", String, callback, queue_size=10)
    print("subscriber:", sub.name, sub.type)
    rospy.Timer(rospy.Duration(10), lambda event: rospy.signal_shutdown("timeout"), oneshot=True)
    rospy.spin()
    print("listener done:", received)


if __name__ == "__main__":
    listener()
