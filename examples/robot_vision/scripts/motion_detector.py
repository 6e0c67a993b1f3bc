#!/usr/bin/env python
# -*- coding: utf-8 -*-
# Motion in front of the camera: each picture compared with the first one; whatever changed
# (larger than ~minArea pixels) is boxed in green, and the room's status written on top.

import rospy
import cv2
import numpy as np
from cv_bridge import CvBridge, CvBridgeError
from sensor_msgs.msg import Image


class motionDetector:
    def __init__(self):
        rospy.on_shutdown(self.cleanup)

        self.minArea = rospy.get_param("~minArea", 500)
        self.threshold = rospy.get_param("~threshold", 25)
        self.firstFrame = None
        self.text = "Unoccupied"

        self.bridge = CvBridge()
        self.image_pub = rospy.Publisher("cv_bridge_image", Image, queue_size=1)
        self.image_sub = rospy.Subscriber("input_rgb_image", Image, self.image_callback,
                                          queue_size=1)

    def image_callback(self, data):
        try:
            cv_image = self.bridge.imgmsg_to_cv2(data, "bgr8")
            frame = np.array(cv_image, dtype=np.uint8)
        except CvBridgeError as e:
            print(e)
            return

        # grey and blurred, so that noise is no motion
        gray = cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY)
        gray = cv2.GaussianBlur(gray, (21, 21), 0)
        if self.firstFrame is None:
            self.firstFrame = gray
            return

        # what differs from the first picture, thickened into regions
        frameDelta = cv2.absdiff(self.firstFrame, gray)
        thresh = cv2.threshold(frameDelta, self.threshold, 255, cv2.THRESH_BINARY)[1]
        thresh = cv2.dilate(thresh, None, iterations=2)
        cnts = cv2.findContours(thresh.copy(), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)[-2]

        self.text = "Unoccupied"
        for c in cnts:
            if cv2.contourArea(c) < self.minArea:
                continue
            (x, y, w, h) = cv2.boundingRect(c)
            cv2.rectangle(frame, (x, y), (x + w, y + h), (0, 255, 0), 2)
            self.text = "Occupied"

        cv2.putText(frame, "Room Status: {}".format(self.text), (10, 20),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 255), 2)
        cv2.imshow("Motion", frame)
        cv2.waitKey(3)

        self.image_pub.publish(self.bridge.cv2_to_imgmsg(frame, "bgr8"))

    def cleanup(self):
        print("Shutting down vision node.")
        cv2.destroyAllWindows()


if __name__ == '__main__':
    try:
        rospy.init_node("motion_detector")
        motionDetector()
        rospy.loginfo("Motion detector is started..")
        rospy.loginfo("Please subscribe the ROS image.")
        rospy.spin()
    except KeyboardInterrupt:
        print("Shutting down motion detector node.")
        cv2.destroyAllWindows()
