"""rospy.client (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import get_param, init_node, myargv, on_shutdown, spin, wait_for_message

__all__ = ["get_param", "init_node", "myargv", "on_shutdown", "spin", "wait_for_message"]
