#!/usr/bin/env python
# Serves the do_dishes action: five steps of feedback, then a result.
import actionlib
import rospy
from learning_action.msg import DoDishesAction, DoDishesFeedback, DoDishesResult


class DishwasherServer:
    def __init__(self):
        self.server = actionlib.SimpleActionServer(
            "do_dishes", DoDishesAction, self.execute, auto_start=False
        )
        self.server.start()

    def execute(self, goal):
        rospy.loginfo("Dishwasher %d is working.", goal.dishwasher_id)
        rate = rospy.Rate(20)
        feedback = DoDishesFeedback()
        for step in range(1, 6):
            feedback.percent_complete = step * 20.0
            self.server.publish_feedback(feedback)
            rate.sleep()
        rospy.loginfo("Dishwasher %d finished working.", goal.dishwasher_id)
        self.server.set_succeeded(DoDishesResult(total_dishes_cleaned=10))


if __name__ == "__main__":
    rospy.init_node("do_dishes_server")
    DishwasherServer()
    rospy.spin()
