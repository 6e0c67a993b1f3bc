#!/usr/bin/env python3
"""std_srvs servers: SetBool, Trigger, Empty, and a Trigger whose handler raises."""

import rospy
from std_srvs.srv import Empty, EmptyResponse, SetBool, SetBoolResponse, Trigger, TriggerResponse

state = {"enabled": False, "calls": 0, "done": False}


def handle_set(req):
    state["calls"] += 1
    state["enabled"] = req.data
    rospy.loginfo("set_enabled(%s)", req.data)
    return SetBoolResponse(success=True, message="enabled" if req.data else "disabled")


def handle_trigger(req):
    state["calls"] += 1
    print("trigger request:", type(req).__name__)
    return TriggerResponse(True, "triggered, enabled=%s" % state["enabled"])


def handle_tuple(req):
    state["calls"] += 1
    return False, "as a tuple"


def handle_broken(req):
    state["calls"] += 1
    raise ValueError("sensor not ready")


def handle_finish(req):
    state["calls"] += 1
    state["done"] = True
    return EmptyResponse()


rospy.init_node("service_server")
rospy.Service("set_enabled", SetBool, handle_set)
rospy.Service("/trigger", Trigger, handle_trigger)
rospy.Service("~tuple", Trigger, handle_tuple)
rospy.Service("broken", Trigger, handle_broken)
rospy.Service("finish", Empty, handle_finish)
print("services up")
deadline = rospy.get_time() + 10
while not rospy.is_shutdown() and not state["done"] and rospy.get_time() < deadline:
    rospy.sleep(0.02)
rospy.sleep(0.3)  # let the last response go out
rospy.loginfo("served %d calls", state["calls"])
rospy.signal_shutdown("finished")
