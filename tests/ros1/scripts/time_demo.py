#!/usr/bin/env python3
"""Time and Duration arithmetic and reprs, Rate, sleep, and Timers."""

import rospy

rospy.init_node("time_demo")
t = rospy.Time(5, 500)
d = rospy.Duration(1, 250000000)
print("time:", t, repr(t), t.secs, t.nsecs, t.to_sec(), t.to_nsec())
print("duration:", d, repr(d), d.to_sec(), d.to_nsec())
print("t + d:", repr(t + d), "d + t:", repr(d + t))
print("t - d:", repr(t - d), "t - t:", repr(t - rospy.Time(2)))
print("d * 3:", repr(d * 3), "d / 2:", repr(d / 2), "d // 2:", repr(d // 2), "-d:", repr(-d))
print("abs:", repr(abs(rospy.Duration(-3))), "neg secs:", repr(rospy.Duration(-1.5)))
print("from_sec:", repr(rospy.Time.from_sec(1.5)), repr(rospy.Duration.from_sec(0.001)))
print("normalize:", repr(rospy.Time(1, 1500000000)), repr(rospy.Duration(0, -1)))
print("compare:", t < t + d, rospy.Time(1) == rospy.Time(1, 0), d > rospy.Duration(1))
print("zero:", rospy.Time().is_zero(), rospy.Duration().is_zero(), bool(rospy.Time()))
print("hash equal:", hash(rospy.Time(3)) == hash(rospy.Time(3, 0)))
try:
    t + t
except TypeError as err:
    print("TypeError:", err)
try:
    rospy.Time(-1)
except Exception as err:  # noqa
    print(type(err).__name__, err)
print(
    "now is Time:",
    type(rospy.Time.now()).__name__,
    type(rospy.get_rostime()).__name__,
    type(rospy.get_time()).__name__,
)

start = rospy.get_time()
rospy.sleep(0.05)
rospy.sleep(rospy.Duration(0.05))
print("slept at least 0.1:", rospy.get_time() - start >= 0.1)
rate = rospy.Rate(20)
begin = rospy.Time.now()
for _ in range(4):
    rate.sleep()
print("rate loop at least 0.15:", (rospy.Time.now() - begin).to_sec() >= 0.15)
print("remaining is Duration:", type(rate.remaining()).__name__)

ticks = []


def periodic(event):
    ticks.append(event)
    print(
        "tick",
        len(ticks),
        "last_expected None:",
        event.last_expected is None,
        "last_real None:",
        event.last_real is None,
        "types:",
        type(event.current_expected).__name__,
        type(event.current_real).__name__,
    )
    if len(ticks) > 1:
        print("  expected step:", repr(event.current_expected - event.last_expected))


def once(event):
    print("oneshot fired:", type(event).__name__, event.last_duration)


timer = rospy.Timer(rospy.Duration(0.05), periodic)
rospy.Timer(rospy.Duration(0.02), once, oneshot=True)
deadline = rospy.get_time() + 5
while len(ticks) < 3 and rospy.get_time() < deadline:
    rospy.sleep(0.01)
timer.shutdown()
rospy.sleep(0.15)
print("ticks after shutdown:", len(ticks))
rospy.loginfo("time demo done")
