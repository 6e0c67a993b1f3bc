#!/usr/bin/env python3
"""wait_for_message: with a publisher, and on a topic nobody publishes (timeout)."""

import rospy
from std_msgs.msg import String
from std_srvs.srv import Empty

rospy.init_node("waiter")
msg = rospy.wait_for_message("/ready", String, timeout=10)
rospy.loginfo("got %r", msg.data)
print(type(msg).__name__, msg)
try:
    rospy.wait_for_message("/nobody_publishes_this", String, timeout=0.3)
    print("unexpected message")
except rospy.ROSException as err:
    print("ROSException:", err)
    print(type(err).__name__, isinstance(err, rospy.exceptions.ROSException))
try:
    rospy.wait_for_message("relative_topic", String, timeout=rospy.Duration(0.2))
except rospy.ROSException as err:
    rospy.logwarn("%s", err)
rospy.wait_for_service("/ready_publisher/stop", timeout=10)
rospy.ServiceProxy("/ready_publisher/stop", Empty)()
print("waiter done")
