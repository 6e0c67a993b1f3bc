#!/usr/bin/env python
# Serves /show_person (learning_service/Person): prints the person, answers "OK".
import rospy
from learning_service.srv import Person, PersonResponse


def person_callback(req):
    rospy.loginfo("Person: name:%s  age:%d  sex:%d", req.name, req.age, req.sex)
    return PersonResponse("OK")


def person_server():
    rospy.init_node("person_server")
    rospy.Service("/show_person", Person, person_callback)
    print("Ready to show person information.")
    rospy.spin()


if __name__ == "__main__":
    person_server()
