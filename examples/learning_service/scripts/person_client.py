#!/usr/bin/env python
# Calls /show_person once with a learning_service/Person request and prints the answer.
import sys

import rospy
from learning_service.srv import Person, PersonRequest


def person_client():
    rospy.init_node("person_client")
    rospy.wait_for_service("/show_person")
    try:
        show_person = rospy.ServiceProxy("/show_person", Person)
        response = show_person("Tom", 20, PersonRequest.male)
    except rospy.ServiceException as e:
        print("Service call failed: %s" % e)
        sys.exit(1)
    return response.result


if __name__ == "__main__":
    print("Show person result : %s" % person_client())
