#!/usr/bin/env python3
"""Names: the node's name and namespace, resolving, argv and remaps."""

import sys

import rospy
from std_msgs.msg import String

rospy.init_node("names_demo")
print("name:", rospy.get_name())
print("namespace:", rospy.get_namespace())
print("caller id:", rospy.get_caller_id())
for name in ("chatter", "~private", "/global", "sub/topic", "~", "other"):
    print("resolve %r -> %s" % (name, rospy.resolve_name(name)))
print("myargv:", rospy.myargv(argv=sys.argv)[1:])
pub = rospy.Publisher("chatter", String, queue_size=1)
print("publisher resolved:", pub.resolved_name, pub.name)
sub = rospy.Subscriber("other", String, lambda m: None)
print("subscriber resolved:", sub.resolved_name)
print("param private:", rospy.get_param("~rate", "unset"))
print("is_shutdown:", rospy.is_shutdown())
pub.unregister()
sub.unregister()
