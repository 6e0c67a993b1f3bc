"""Simulation engines: the kinematic (ArbotiX-style) engine and, later, physics.

Both take the same robot model and speak the same topics (``/odom``, ``/tf``,
``/joint_states``); the kinematic one moves the robot exactly as commanded, with no physics.
"""
