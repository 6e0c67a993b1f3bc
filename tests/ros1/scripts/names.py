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
rospy.set_param("/top_key", 1)
rospy.set_param("near_key", 2)
for key in ("top_key", "near_key", "nowhere", "~near_key"):
    try:
        print("search_param %r -> %s" % (key, rospy.search_param(key)))
    except rospy.ROSException as err:
        print("search_param %r: %s" % (key, err))
print("is_shutdown:", rospy.is_shutdown())
pub.unregister()
sub.unregister()
