#!/usr/bin/env python3
"""Publishes "go" on /ready at 10 Hz until the waiter calls ~stop."""

import rospy
from std_msgs.msg import String
from std_srvs.srv import Empty, EmptyResponse

stopped = []


def stop(req):
    stopped.append(True)
    return EmptyResponse()


rospy.init_node("ready_publisher")
pub = rospy.Publisher("/ready", String, queue_size=1)
rospy.Service("~stop", Empty, stop)
rate = rospy.Rate(10)
deadline = rospy.get_time() + 10
while not rospy.is_shutdown() and not stopped and rospy.get_time() < deadline:
    pub.publish("go")
    rate.sleep()
rospy.sleep(0.2)  # let the stop call's answer go out
rospy.loginfo("stopped by the waiter: %s", bool(stopped))
