#!/usr/bin/env python3
"""The ROS tutorial talker: five counted messages on chatter at 10 Hz."""

import rospy
from std_msgs.msg import String


def talker():
    pub = rospy.Publisher("chatter", String, queue_size=10)
    rospy.init_node("talker")
    print("publisher:", pub.name, pub.type, pub.resolved_name)
    rate = rospy.Rate(10)
    # wait for the listener, as the tutorials teach, so the first message is not lost
    deadline = rospy.get_time() + 10
    while pub.get_num_connections() == 0 and rospy.get_time() < deadline:
        rospy.sleep(0.01)
    print("connections:", pub.get_num_connections())
    count = 0
    while not rospy.is_shutdown() and count < 5:
        hello_str = "hello world %d" % count
        rospy.loginfo(hello_str)
        pub.publish(hello_str)
        count += 1
        rate.sleep()
    # stay until the listener has had them all and left
    deadline = rospy.get_time() + 10
    while pub.get_num_connections() > 0 and rospy.get_time() < deadline:
        rospy.sleep(0.01)
    print("talker done, sent", count)


if __name__ == "__main__":
    try:
        talker()
    except rospy.ROSInterruptException:
        pass
