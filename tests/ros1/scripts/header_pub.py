#!/usr/bin/env python3
"""Messages with a Header: rospy numbers them (header.seq) as it publishes."""

import rospy
from geometry_msgs.msg import PoseStamped

rospy.init_node("header_pub")
pub = rospy.Publisher("/pose", PoseStamped, queue_size=10)
deadline = rospy.get_time() + 10
while pub.get_num_connections() == 0 and rospy.get_time() < deadline:
    rospy.sleep(0.01)
for i in range(4):
    msg = PoseStamped()
    msg.header.frame_id = "map"
    if i == 2:
        msg.header.seq = 100
    msg.pose.position.x = float(i)
    pub.publish(msg)
    print("published seq after publish:", msg.header.seq, "stamp zero:", msg.header.stamp.is_zero())
    rospy.sleep(0.02)
while pub.get_num_connections() > 0 and rospy.get_time() < deadline:
    rospy.sleep(0.01)
