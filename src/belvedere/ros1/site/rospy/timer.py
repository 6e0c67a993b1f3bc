"""rospy.timer (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import Rate, Timer, TimerEvent, sleep

__all__ = ["Rate", "Timer", "TimerEvent", "sleep"]
