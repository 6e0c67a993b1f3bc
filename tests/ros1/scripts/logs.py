#!/usr/bin/env python3
"""Log functions: levels, streams, format arguments, _throttle and _once, and /rosout."""

import rospy
from rosgraph_msgs.msg import Log

seen = []


def on_rosout(msg):
    if msg.name == rospy.get_name():
        seen.append(msg)


rospy.init_node("log_demo")
rospy.loginfo("node up")  # latched on /rosout: the subscriber below gets it first
sub = rospy.Subscriber("/rosout", Log, on_rosout, queue_size=100)
deadline = rospy.get_time() + 10
while not seen and rospy.get_time() < deadline:
    rospy.sleep(0.01)
rospy.logdebug("debug is hidden at the default level")
rospy.loginfo("info %d %s", 1, "arg")
rospy.logwarn("a warning")
rospy.logerr("an error: %.2f", 0.5)
rospy.logfatal("fatal!")
rospy.loginfo(42)
rospy.logwarn("percent %% sign")
for i in range(5):
    rospy.loginfo_throttle(60, "throttled info %d" % i)
    rospy.logwarn_throttle(60, "throttled warn")
    rospy.loginfo_once("once %d" % i)
    rospy.logerr_once("err once")
    rospy.logdebug_throttle(60, "debug throttled")
    rospy.sleep(0.01)
print("plain print between logs")
rospy.loginfo("last")
while len(seen) < 12 and rospy.get_time() < deadline:
    rospy.sleep(0.01)
sub.unregister()
names = {
    Log.DEBUG: "DEBUG",
    Log.INFO: "INFO",
    Log.WARN: "WARN",
    Log.ERROR: "ERROR",
    Log.FATAL: "FATAL",
}
for m in seen:
    print(
        "rosout:",
        names[m.level],
        m.level,
        m.name,
        repr(m.msg),
        m.header.frame_id == "",
        sorted(m.topics),
    )
