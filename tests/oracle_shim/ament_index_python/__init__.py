"""Test-only stand-in for ROS 2's package index, so the xacro 2.1.1 oracle can run $(find)."""
