#!/usr/bin/env python
# Publishes learning_topic/Person on /person_info, ten times a second.
import rospy
from learning_topic.msg import Person


def person_publisher():
    rospy.init_node("person_publisher", anonymous=True)
    pub = rospy.Publisher("/person_info", Person, queue_size=10)
    rate = rospy.Rate(10)
    count = 0
    while not rospy.is_shutdown():
        msg = Person()
        msg.name = "Tom"
        msg.age = 18
        msg.sex = Person.male
        pub.publish(msg)
        rospy.loginfo("Publish Person Info: name:%s  age:%d  sex:%d", msg.name, msg.age, msg.sex)
        count += 1
        rate.sleep()


if __name__ == "__main__":
    try:
        person_publisher()
    except rospy.ROSInterruptException:
        pass
