"""rospy.names (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import get_caller_id, get_name, get_namespace, remap_name, resolve_name

__all__ = ["get_caller_id", "get_name", "get_namespace", "remap_name", "resolve_name"]
