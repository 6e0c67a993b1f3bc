#!/usr/bin/env python3
"""A 10 Hz velocity loop on /cmd_vel: six Twists, speeding up, then a stop."""

import rospy
from geometry_msgs.msg import Twist

rospy.init_node("drive")
pub = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
deadline = rospy.get_time() + 10
while pub.get_num_connections() == 0 and rospy.get_time() < deadline:
    rospy.sleep(0.01)
rate = rospy.Rate(10)
for i in range(6):
    cmd = Twist()
    cmd.linear.x = 0.1 * i
    cmd.angular.z = -0.5 if i % 2 else 0.5
    pub.publish(cmd)
    rate.sleep()
stop = Twist()
pub.publish(stop)
rospy.loginfo("sent stop: %s", stop.linear.x)
while pub.get_num_connections() > 0 and rospy.get_time() < deadline:
    rospy.sleep(0.01)
