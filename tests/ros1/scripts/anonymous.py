#!/usr/bin/env python3
"""An anonymous node: its name gets a suffix."""

import rospy

rospy.init_node("anon_node", anonymous=True)
name = rospy.get_name()
print("name:", name)
print("starts with /anon_node_:", name.startswith("/anon_node_"))
print("private:", rospy.resolve_name("~x"))
rospy.loginfo("I am %s", name)
