#!/usr/bin/env python3
"""Send move_base a few goals through actionlib, as the book's exploration and nav_test demos
do, and report how each ended. Goals: ~goals, a list of [x, y, yaw] in the map frame."""

import math

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Point, Pose, Quaternion
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal

STATES = [
    "PENDING",
    "ACTIVE",
    "PREEMPTED",
    "SUCCEEDED",
    "ABORTED",
    "REJECTED",
    "PREEMPTING",
    "RECALLING",
    "RECALLED",
    "LOST",
]


def main():
    rospy.init_node("nav_goals")
    goals = rospy.get_param("~goals", [[1.0, 0.0, 0.0], [1.0, 1.0, 1.57]])
    client = actionlib.SimpleActionClient("move_base", MoveBaseAction)
    rospy.loginfo("Waiting for move_base action server...")
    if not client.wait_for_server(rospy.Duration(60)):
        rospy.logerr("no move_base action server")
        return 1
    reached = 0
    for x, y, yaw in goals:
        goal = MoveBaseGoal()
        goal.target_pose.header.frame_id = "map"
        goal.target_pose.header.stamp = rospy.Time.now()
        goal.target_pose.pose = Pose(
            Point(x, y, 0.0), Quaternion(0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
        )
        rospy.loginfo("Going to (%.2f, %.2f)", x, y)
        client.send_goal(goal)
        if not client.wait_for_result(rospy.Duration(120)):
            client.cancel_goal()
            rospy.loginfo("Timed out achieving goal")
            continue
        state = client.get_state()
        rospy.loginfo("Goal ended: %s", STATES[state])
        reached += state == GoalStatus.SUCCEEDED
    rospy.loginfo("Reached %d of %d goals", reached, len(goals))
    return 0 if reached == len(goals) else 1


if __name__ == "__main__":
    raise SystemExit(main())
