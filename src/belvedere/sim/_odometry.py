"""A simulated base's ``nav_msgs/Odometry``: the one message every drive plugin publishes.

The drives (Gazebo's diff drive, skid steer and planar move, ros_control's diff drive
controller, the ArbotiX fake base) differ in how they come by the pose and twist, not in
what they publish; the message is built only when someone listens, as it is the cost.
"""

from __future__ import annotations

from belvedere.graph import Publisher
from belvedere.msgs import build

__all__ = ["publish_odometry"]


def publish_odometry(
    pub: Publisher,
    stamp_ns: int,
    frames: tuple[str, str],
    position: build.Floats,
    quat: build.Floats,
    linear: build.Floats,
    angular: build.Floats,
    *,
    pose_covariance: build.Floats | None = None,
    twist_covariance: build.Floats | None = None,
) -> None:
    """``frames`` is (odom frame, base frame): the header's and the child's."""
    if not pub.wanted:
        return
    odom_frame, base_frame = frames
    pub.publish(
        build.odometry(
            stamp_ns=stamp_ns,
            frame_id=odom_frame,
            child_frame_id=base_frame,
            position=position,
            quat_xyzw=quat,
            linear=linear,
            angular=angular,
            pose_covariance=pose_covariance,
            twist_covariance=twist_covariance,
            seq=pub.next_seq(),
        )
    )
