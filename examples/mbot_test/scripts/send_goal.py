#!/usr/bin/env python3
"""A rostest node: send the mbot a navigation goal through move_base's action, as the course's
2D Nav Goal does, and check that move_base reached it and that odometry agrees (within
~tolerance metres)."""

import math
import sys
import unittest

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import Odometry

import rostest

PKG = "mbot_test"
NAME = "send_goal"


class SendGoal(unittest.TestCase):
    def test_reaches_goal(self):
        x = float(rospy.get_param("~x"))
        y = float(rospy.get_param("~y"))
        yaw = float(rospy.get_param("~yaw", 0.0))
        tolerance = float(rospy.get_param("~tolerance", 0.2))
        client = actionlib.SimpleActionClient("move_base", MoveBaseAction)
        self.assertTrue(client.wait_for_server(rospy.Duration(30.0)), "no move_base")

        goal = MoveBaseGoal()
        goal.target_pose.header.frame_id = "map"
        goal.target_pose.header.stamp = rospy.Time.now()
        goal.target_pose.pose.position.x = x
        goal.target_pose.pose.position.y = y
        goal.target_pose.pose.orientation.z = math.sin(yaw / 2)
        goal.target_pose.pose.orientation.w = math.cos(yaw / 2)
        client.send_goal(goal)
        # simulated seconds: the run goes as fast as the CPU allows
        self.assertTrue(client.wait_for_result(rospy.Duration(120.0)), "no result in 120 s")
        self.assertEqual(client.get_state(), GoalStatus.SUCCEEDED, client.get_goal_status_text())

        # in the simulation the map's frame is the world's, and odometry is the true pose
        odom = rospy.wait_for_message("/odom", Odometry, timeout=10.0)
        where = odom.pose.pose.position
        off = math.hypot(where.x - x, where.y - y)
        self.assertLess(off, tolerance, f"stopped at ({where.x:.2f}, {where.y:.2f})")


if __name__ == "__main__":
    rospy.init_node(NAME)
    rostest.rosrun(PKG, NAME, SendGoal, sys.argv)
