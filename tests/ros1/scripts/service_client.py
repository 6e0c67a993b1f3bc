#!/usr/bin/env python3
"""Calls the std_srvs servers, a handler that raises, and a service nobody offers."""

import rospy
from std_srvs.srv import Empty, SetBool, SetBoolRequest, Trigger

rospy.init_node("service_client")
rospy.wait_for_service("set_enabled", timeout=10)
rospy.wait_for_service("/finish", timeout=rospy.Duration(10))
rospy.wait_for_service("/service_server/tuple", timeout=10)
set_enabled = rospy.ServiceProxy("set_enabled", SetBool)
print("proxy:", set_enabled.resolved_name)
resp = set_enabled(True)
print("SetBool(True):", resp.success, resp.message)
print(resp)
resp = set_enabled.call(SetBoolRequest(data=False))
print("SetBool(False):", repr(resp.message))
resp = set_enabled(data=True)
print("SetBool(data=True):", resp.message)

trigger = rospy.ServiceProxy("/trigger", Trigger, persistent=False)
r = trigger()
print("Trigger:", r.success, r.message, type(r).__name__)
print("tuple handler:", rospy.ServiceProxy("/service_server/tuple", Trigger)().message)

broken = rospy.ServiceProxy("broken", Trigger)
try:
    broken()
except rospy.ServiceException as err:
    print("ServiceException:", err)
    print(type(err).__name__, isinstance(err, rospy.ROSException))

try:
    rospy.wait_for_service("/missing_service", timeout=0.3)
except rospy.ROSException as err:
    rospy.logerr("wait_for_service: %s", err)

try:
    rospy.ServiceProxy("/missing_service", Trigger)()
except rospy.ServiceException as err:
    print("missing:", err)

persistent = rospy.ServiceProxy("set_enabled", SetBool, persistent=True)
print([persistent(flag).message for flag in (True, False, True)])
persistent.close()

try:
    set_enabled("yes")
except Exception as err:  # noqa
    print(type(err).__name__)

finish = rospy.ServiceProxy("finish", Empty)
print("Empty:", repr(finish()))
print("client done")
