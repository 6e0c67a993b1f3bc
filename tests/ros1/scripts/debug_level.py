#!/usr/bin/env python3
"""init_node(log_level=rospy.DEBUG) shows logdebug."""

import rospy

rospy.init_node("debug_node", log_level=rospy.DEBUG)
rospy.logdebug("script: now debug shows: %s", rospy.get_name())
rospy.loginfo("script: info still shows")
rospy.logdebug("script: %d of %d", 2, 2)
