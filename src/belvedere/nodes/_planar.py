"""The 2-D navigation nodes' view of TF: stamps, rotations and transforms in the plane, where
the laser sits on the base, and a buffer that tells them when it learnt a transform."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.graph import NS, Node
from belvedere.nav._input import Tally, pose_problem
from belvedere.tf import TFBuffer, TFError, Transform

__all__ = [
    "MOUNT_REFUSED",
    "laser_mount",
    "listen_then",
    "planar",
    "stamp_ns",
    "usable_mount",
    "yaw_of",
    "yaw_quat",
]

MOUNT_REFUSED = "skipped {count}: the laser's mount on the base is "
"""The tally's template for a scan whose laser mount is not finite or too far."""


def stamp_ns(msg: Any) -> int:
    """A stamped message's stamp in nanoseconds."""
    stamp = msg.header.stamp
    return int(stamp.sec) * NS + int(stamp.nanosec)


def yaw_of(quat_xyzw: tuple[float, float, float, float]) -> float:
    """The rotation about z of a quaternion (x, y, z, w)."""
    # the yaw alone: these nodes read it per scan or reading, and never need roll or pitch
    x, y, z, w = quat_xyzw
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def yaw_quat(yaw: float) -> tuple[float, float, float, float]:
    """The quaternion (x, y, z, w) of a rotation by ``yaw`` about z."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def planar(transform: Transform) -> npt.NDArray[np.float64]:
    """(x, y, yaw) of a transform."""
    return np.array(
        [transform.translation[0], transform.translation[1], yaw_of(transform.quat_xyzw)]
    )


def laser_mount(buffer: TFBuffer, base: str, frame: str, stamp: int) -> Transform:
    """The laser's pose on the base at ``stamp``, else the latest one: a mount published
    once (on ``/tf_static``, or long before the scan) still holds.

    Raises:
        TFError: neither is known.
    """
    try:
        return buffer.lookup_transform(base, frame, stamp)
    except TFError:
        return buffer.lookup_transform(base, frame, 0)


def usable_mount(
    buffer: TFBuffer, base: str, frame: str, stamp: int, tally: Tally
) -> Transform | None:
    """:func:`laser_mount`, or None (counted in ``tally``) when it is not finite or too far.

    Raises:
        TFError: the mount is not known.
    """
    mount = laser_mount(buffer, base, frame, stamp)
    problem = pose_problem([*mount.translation, *mount.quat_xyzw])
    if tally.refused(problem, at=f"{stamp / NS:.3f} s", template=MOUNT_REFUSED):
        return None
    return mount


def listen_then(node: Node, buffer: TFBuffer, then: Callable[[], None]) -> None:
    """Fill ``buffer`` from ``/tf`` and ``/tf_static``, calling ``then`` after each message:
    inputs that wait for a transform (tf's message filter) are retried when one arrives."""

    def on_tf(msg: Any) -> None:
        buffer.set_message(msg)
        then()

    def on_tf_static(msg: Any) -> None:
        buffer.set_message(msg, static=True)
        then()

    node.subscribe("/tf", "tf2_msgs/TFMessage", on_tf, queue_size=100)
    node.subscribe("/tf_static", "tf2_msgs/TFMessage", on_tf_static, queue_size=100)
