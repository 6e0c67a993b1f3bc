"""rospy.topics (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import Message, Publisher, SubscribeListener, Subscriber

__all__ = ["Message", "Publisher", "SubscribeListener", "Subscriber"]
