#!/usr/bin/env python
# Prints each learning_topic/Person heard on /person_info.
import rospy
from learning_topic.msg import Person

SEXES = {Person.unknown: "unknown", Person.male: "male", Person.female: "female"}


def person_info_callback(msg):
    rospy.loginfo(
        "Subscribe Person Info: name:%s  age:%d  sex:%s", msg.name, msg.age, SEXES[msg.sex]
    )


def person_subscriber():
    rospy.init_node("person_subscriber", anonymous=True)
    rospy.Subscriber("/person_info", Person, person_info_callback)
    rospy.spin()


if __name__ == "__main__":
    person_subscriber()
