#!/usr/bin/env python3
"""A rostest node: drive the mbot to a point ahead with cmd_vel and check, from odometry, that
it got there (within ~tolerance metres) and went straight."""

import math
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

PKG = "mbot_test"
NAME = "drive_to_goal"


class DriveToGoal(unittest.TestCase):
    def setUp(self):
        self.odom = None
        rospy.Subscriber("/odom", Odometry, self.on_odom)
        self.cmd = rospy.Publisher("/cmd_vel", Twist, queue_size=1)

    def on_odom(self, msg):
        self.odom = msg.pose.pose.position

    def test_reaches_goal(self):
        goal = float(rospy.get_param("~goal_x", 1.0))
        tolerance = float(rospy.get_param("~tolerance", 0.1))
        rospy.wait_for_message("/odom", Odometry, timeout=30.0)
        forward = Twist()
        forward.linear.x = 0.2
        deadline = rospy.get_time() + 4.0 * goal / forward.linear.x
        rate = rospy.Rate(20)
        # drive until odometry says the goal is reached (or the simulated deadline passes)
        while not rospy.is_shutdown() and rospy.get_time() < deadline:
            if self.odom is not None and self.odom.x >= goal - tolerance / 2:
                break
            self.cmd.publish(forward)
            rate.sleep()
        for _ in range(5):
            self.cmd.publish(Twist())
            rate.sleep()
        rospy.sleep(1.0)
        self.assertIsNotNone(self.odom, "no odometry")
        self.assertLess(abs(self.odom.x - goal), tolerance, "stopped at x=%.3f" % self.odom.x)
        self.assertLess(abs(self.odom.y), tolerance, "drifted to y=%.3f" % self.odom.y)
        self.assertTrue(math.isfinite(self.odom.z))


if __name__ == "__main__":
    rospy.init_node(NAME)
    rostest.rosrun(PKG, NAME, DriveToGoal, sys.argv)
