#!/usr/bin/env python3
"""on_shutdown hooks, signal_shutdown's reason, and what sleeping does after shutdown."""

import rospy


def first_hook():
    print("hook 1: is_shutdown =", rospy.is_shutdown())


def second_hook():
    print("hook 2")
    rospy.loginfo("logging from a shutdown hook")


rospy.init_node("shutdown_demo")
rospy.on_shutdown(first_hook)
rospy.on_shutdown(second_hook)
rospy.core.add_preshutdown_hook(lambda reason: print("preshutdown, reason:", reason))
print("before:", rospy.is_shutdown(), rospy.core.is_shutdown_requested())
rate = rospy.Rate(50)
n = 0
while not rospy.is_shutdown():
    n += 1
    if n == 3:
        rospy.signal_shutdown("enough loops")
        print("after signal:", rospy.is_shutdown())
    try:
        rate.sleep()
    except rospy.ROSInterruptException as err:
        print("rate.sleep:", type(err).__name__, err)
print("loops:", n)
try:
    rospy.sleep(0.1)
except rospy.ROSInterruptException as err:
    print("sleep after shutdown:", err)
rospy.on_shutdown(lambda: print("late hook"))
rospy.signal_shutdown("second time")
print("end")
