#!/usr/bin/env python3
"""Explore while mapping, as the course's exploring_slam demo does: send move_base goals
through actionlib one after another (~goals, a list of [x, y, yaw] in the map frame; the
course draws them at random) and say after each how much of the map gmapping knows."""

import math

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Point, Pose, Quaternion
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import OccupancyGrid


class Explorer:
    def __init__(self):
        self.known_m2 = 0.0
        rospy.Subscriber("map", OccupancyGrid, self.on_map, queue_size=1)
        self.client = actionlib.SimpleActionClient("move_base", MoveBaseAction)

    def on_map(self, grid):
        known = sum(1 for value in grid.data if value >= 0)
        self.known_m2 = known * grid.info.resolution**2

    def go(self, x, y, yaw, timeout):
        goal = MoveBaseGoal()
        goal.target_pose.header.frame_id = "map"
        goal.target_pose.header.stamp = rospy.Time.now()
        goal.target_pose.pose = Pose(
            Point(x, y, 0.0), Quaternion(0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
        )
        rospy.loginfo("Exploring towards (%.2f, %.2f)", x, y)
        self.client.send_goal(goal)
        if not self.client.wait_for_result(rospy.Duration(timeout)):
            self.client.cancel_goal()
            rospy.loginfo("Timed out on the way")
            return False
        return self.client.get_state() == GoalStatus.SUCCEEDED


def main():
    rospy.init_node("exploring_slam")
    goals = rospy.get_param("~goals", [[2.0, -4.5, 0.0], [4.5, -4.5, 1.57]])
    timeout = rospy.get_param("~timeout", 120.0)
    explorer = Explorer()
    if not explorer.client.wait_for_server(rospy.Duration(60)):
        rospy.logerr("no move_base action server")
        return 1
    reached = 0
    for x, y, yaw in goals:
        ok = explorer.go(x, y, yaw, timeout)
        reached += ok
        rospy.loginfo(
            "Goal %s; the map knows %.1f m^2", "reached" if ok else "missed", explorer.known_m2
        )
    rospy.loginfo("Reached %d of %d goals", reached, len(goals))
    return 0 if reached == len(goals) else 1


if __name__ == "__main__":
    raise SystemExit(main())
