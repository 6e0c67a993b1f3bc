#!/usr/bin/env python3
# A node for rosnode's tools: the listener subscribes (nothing publishes: unconnected) and
# offers /enable, the talker publishes /status; each notes in DONE that its on_shutdown hook
# ran, and says when rospy.spin() returns (after rosnode kill).
import sys

import rospy
from std_msgs.msg import String
from std_srvs.srv import SetBool, SetBoolResponse

role, done = sys.argv[1], sys.argv[2]
rospy.init_node(role, disable_rosout=True)
if role == "listener":
    rospy.Subscriber("/chatter", String, lambda m: None)
    rospy.Service("/enable", SetBool, lambda req: SetBoolResponse(True, "on"))
else:
    pub = rospy.Publisher("/status", String, queue_size=1)


def hook():
    with open(done, "w") as f:
        f.write("hook ran")


rospy.on_shutdown(hook)
print("ready", flush=True)
rospy.spin()
print("spin returned", flush=True)
