#!/usr/bin/env python
# -*- coding: utf-8 -*-
# Faces in the camera's pictures: OpenCV's Haar cascades (their XML files named by the
# launch file) find them in the equalized grey picture; each is framed in green and the
# picture published again.

import rospy
import cv2
import numpy as np
from cv_bridge import CvBridge, CvBridgeError
from sensor_msgs.msg import Image


class faceDetector:
    def __init__(self):
        rospy.on_shutdown(self.cleanup)

        self.bridge = CvBridge()
        self.image_pub = rospy.Publisher("cv_bridge_image", Image, queue_size=1)

        # the cascades' XML files: the launch file passes their paths
        cascade_1 = rospy.get_param("~cascade_1", "")
        cascade_2 = rospy.get_param("~cascade_2", "")
        self.cascade_1 = cv2.CascadeClassifier(cascade_1)
        self.cascade_2 = cv2.CascadeClassifier(cascade_2)
        if self.cascade_1.empty():
            rospy.logerr("cannot load the Haar cascade %s", cascade_1)

        # the detector's settings, from the launch file
        self.haar_scaleFactor = rospy.get_param("~haar_scaleFactor", 1.2)
        self.haar_minNeighbors = rospy.get_param("~haar_minNeighbors", 2)
        self.haar_minSize = rospy.get_param("~haar_minSize", 40)
        self.haar_maxSize = rospy.get_param("~haar_maxSize", 60)
        self.color = (50, 255, 50)

        self.image_sub = rospy.Subscriber("input_rgb_image", Image, self.image_callback,
                                          queue_size=1)

    def image_callback(self, data):
        try:
            cv_image = self.bridge.imgmsg_to_cv2(data, "bgr8")
            frame = np.array(cv_image, dtype=np.uint8)
        except CvBridgeError as e:
            print(e)
            return

        # grey, with its histogram spread, so that the cascades see contrast
        grey_image = cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY)
        grey_image = cv2.equalizeHist(grey_image)

        faces_result = self.detect_face(grey_image)
        for (x, y, w, h) in faces_result:
            cv2.rectangle(cv_image, (x, y), (x + w, y + h), self.color, 2)

        self.image_pub.publish(self.bridge.cv2_to_imgmsg(cv_image, "bgr8"))

    def detect_face(self, input_image):
        faces = []
        if not self.cascade_1.empty():
            faces = self.cascade_1.detectMultiScale(
                input_image, self.haar_scaleFactor, self.haar_minNeighbors,
                cv2.CASCADE_SCALE_IMAGE, (self.haar_minSize, self.haar_maxSize))
        # the second cascade (faces in profile) only where the first found none
        if len(faces) == 0 and not self.cascade_2.empty():
            faces = self.cascade_2.detectMultiScale(
                input_image, self.haar_scaleFactor, self.haar_minNeighbors,
                cv2.CASCADE_SCALE_IMAGE, (self.haar_minSize, self.haar_maxSize))
        return faces

    def cleanup(self):
        print("Shutting down vision node.")
        cv2.destroyAllWindows()


if __name__ == '__main__':
    try:
        rospy.init_node("face_detector")
        faceDetector()
        rospy.loginfo("Face detector is started..")
        rospy.loginfo("Please subscribe the ROS image.")
        rospy.spin()
    except KeyboardInterrupt:
        print("Shutting down face detector node.")
        cv2.destroyAllWindows()
