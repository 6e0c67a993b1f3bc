#!/usr/bin/env python3
"""Publishes one latched message, then waits for a late subscriber to come and go."""

import rospy
from std_msgs.msg import String

rospy.init_node("map_server_lite")
pub = rospy.Publisher("/map_name", String, queue_size=1, latch=True)
pub.publish(String(data="office floor 2"))
print("published latched")
deadline = rospy.get_time() + 10
while not rospy.is_shutdown() and pub.get_num_connections() == 0 and rospy.get_time() < deadline:
    rospy.sleep(0.01)
print("late subscriber connected:", pub.get_num_connections())
while not rospy.is_shutdown() and pub.get_num_connections() > 0 and rospy.get_time() < deadline:
    rospy.sleep(0.01)
rospy.loginfo("late subscriber gone")
