#!/usr/bin/env python
# Asks the do_dishes action to clean dishwasher 1, printing its feedback and result.
import actionlib
import rospy
from learning_action.msg import DoDishesAction, DoDishesGoal


def feedback_cb(feedback):
    print("Percent complete: %.1f%%" % feedback.percent_complete)


if __name__ == "__main__":
    rospy.init_node("do_dishes_client")
    client = actionlib.SimpleActionClient("do_dishes", DoDishesAction)
    client.wait_for_server()
    goal = DoDishesGoal()
    goal.dishwasher_id = 1
    client.send_goal(goal, feedback_cb=feedback_cb)
    client.wait_for_result(rospy.Duration(30.0))
    print("Result: %d dishes cleaned" % client.get_result().total_dishes_cleaned)
