"""One frame's history as tf2 keeps it (a time cache, or a static one), and tf2's arithmetic
on ``(translation, quat_xyzw)`` pairs: quaternions are not renormalised along a chain, times
are integer nanoseconds and print as ROS's ``sec.nsec``."""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from typing import Final

__all__ = [
    "NS",
    "Quat",
    "StaticCache",
    "Stored",
    "TimeCache",
    "Vec3",
    "compose",
    "conjugate",
    "duration_text",
    "quat_mul",
    "rotate",
    "seconds",
    "slerp",
    "time_text",
]

NS: Final = 1_000_000_000

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]


def time_text(ns: int) -> str:
    """A ``ros::Time`` as C++ prints it: ``12.000000000``."""
    return f"{ns // NS}.{ns % NS:09d}"


def duration_text(ns: int) -> str:
    """A ``ros::Duration`` as C++ prints it (negative ones as ``-0.5`` → ``-0.500000000``)."""
    sec, nsec = divmod(ns, NS)
    if sec >= 0 or nsec == 0:
        return f"{sec}.{nsec:09d}"
    return f"{'-' if sec == -1 else ''}{sec + 1}.{NS - nsec:09d}"


def seconds(ns: int) -> float:
    """``toSec()`` of a time or duration: whole seconds plus 1e-9 times the nanoseconds."""
    sec, nsec = divmod(ns, NS)
    return float(sec) + 1e-9 * float(nsec)


# --- tf2's quaternion and vector arithmetic ------------------------------------------------


def quat_mul(a: Quat, b: Quat) -> Quat:
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by + ay * bw + az * bx - ax * bz,
        aw * bz + az * bw + ax * by - ay * bx,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def conjugate(q: Quat) -> Quat:
    """tf2's ``inverse()``: the conjugate (exact for unit quaternions only)."""
    return (-q[0], -q[1], -q[2], q[3])


def rotate(q: Quat, v: Vec3) -> Vec3:
    """``q * v * q⁻¹`` with tf2's conjugate as the inverse."""
    qx, qy, qz, qw = q
    vx, vy, vz = v
    # q * (v, 0)
    px = qw * vx + qy * vz - qz * vy
    py = qw * vy + qz * vx - qx * vz
    pz = qw * vz + qx * vy - qy * vx
    pw = -qx * vx - qy * vy - qz * vz
    x, y, z, _ = quat_mul((px, py, pz, pw), conjugate(q))
    return (x, y, z)


def compose(t1: Vec3, q1: Quat, t2: Vec3, q2: Quat) -> tuple[Vec3, Quat]:
    """``(t1, q1) ∘ (t2, q2)``: ``q1`` applied to ``t2``, plus ``t1``."""
    rx, ry, rz = rotate(q1, t2)
    return (rx + t1[0], ry + t1[1], rz + t1[2]), quat_mul(q1, q2)


def slerp(a: Quat, b: Quat, t: float) -> Quat:
    """tf2's slerp: the short way round, unnormalised, ``a`` itself when the angle is 0."""
    dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
    norms = math.sqrt(
        (a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3])
        * (b[0] * b[0] + b[1] * b[1] + b[2] * b[2] + b[3] * b[3])
    )
    cosine = max(-1.0, min(1.0, (-dot if dot < 0 else dot) / norms))
    half = math.acos(cosine)  # half the angle between the rotations
    if half == 0.0:
        return a
    d = 1.0 / math.sin(half)
    s0 = math.sin((1.0 - t) * half)
    s1 = math.sin(t * half)
    if dot < 0:
        s1 = -s1
    return (
        (a[0] * s0 + b[0] * s1) * d,
        (a[1] * s0 + b[1] * s1) * d,
        (a[2] * s0 + b[2] * s1) * d,
        (a[3] * s0 + b[3] * s1) * d,
    )


# --- caches --------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Stored:
    """One transform of a frame: to ``parent`` (a frame number) at ``stamp`` (ns)."""

    stamp: int
    parent: int
    translation: Vec3
    rotation: Quat


class TimeCache:
    """A frame's transforms over the last ``max_ns`` nanoseconds, interpolated between."""

    def __init__(self, max_ns: int) -> None:
        self.max_ns = max_ns
        self.stamps: list[int] = []  # oldest first
        self.items: list[Stored] = []

    def insert(self, item: Stored) -> str | None:
        """Store ``item``; or why not (tf2's warning code and reason)."""
        if self.stamps and self.stamps[-1] > item.stamp + self.max_ns:
            return (
                "TF_OLD_DATA ignoring data from the past (Possible reasons are listed at "
                "http://wiki.ros.org/tf/Errors%20explained)"
            )
        i = bisect.bisect_right(self.stamps, item.stamp)
        if i and self.stamps[i - 1] == item.stamp:
            return "TF_REPEATED_DATA ignoring data with redundant timestamp"
        self.stamps.insert(i, item.stamp)
        self.items.insert(i, item)
        drop = bisect.bisect_left(self.stamps, self.stamps[-1] - self.max_ns)
        if drop:
            del self.stamps[:drop]
            del self.items[:drop]
        return None

    def clear(self) -> None:
        self.stamps.clear()
        self.items.clear()

    def _closest(self, time_ns: int) -> tuple[Stored, Stored | None] | str:
        """The stored transform at ``time_ns`` (0: the latest), or the two around it, or why
        there is none (tf2's texts)."""
        if not self.items:
            return ""  # tf2 gives no reason
        if time_ns == 0:
            return self.items[-1], None
        if len(self.items) == 1:
            only = self.items[0]
            if only.stamp == time_ns:
                return only, None
            return (
                f"Lookup would require extrapolation at time {time_text(time_ns)}, "
                f"but only time {time_text(only.stamp)} is in the buffer"
            )
        latest, earliest = self.stamps[-1], self.stamps[0]
        if time_ns == latest:
            return self.items[-1], None
        if time_ns == earliest:
            return self.items[0], None
        if time_ns > latest:
            return (
                f"Lookup would require extrapolation {duration_text(time_ns - latest)}s into "
                f"the future.  Requested time {time_text(time_ns)} but the latest data is at "
                f"time {time_text(latest)}"
            )
        if time_ns < earliest:
            return (
                f"Lookup would require extrapolation {duration_text(earliest - time_ns)}s into "
                f"the past.  Requested time {time_text(time_ns)} but the earliest data is at "
                f"time {time_text(earliest)}"
            )
        i = bisect.bisect_right(self.stamps, time_ns) - 1  # the newest at or before time_ns
        return self.items[i], self.items[i + 1]

    def get(self, time_ns: int) -> Stored | str:
        """The transform at ``time_ns``: interpolated between the two around it when both
        have the same parent, else the older one."""
        found = self._closest(time_ns)
        if isinstance(found, str):
            return found
        one, two = found
        if two is None or two.parent != one.parent:
            return one
        ratio = seconds(time_ns - one.stamp) / seconds(two.stamp - one.stamp)
        rest = 1.0 - ratio
        a, b = one.translation, two.translation
        return Stored(
            one.stamp,
            one.parent,
            (
                rest * a[0] + ratio * b[0],
                rest * a[1] + ratio * b[1],
                rest * a[2] + ratio * b[2],
            ),
            slerp(one.rotation, two.rotation, ratio),
        )

    def latest_and_parent(self) -> tuple[int, int]:
        """(stamp, parent) of the newest transform; (0, 0) when empty."""
        if not self.items:
            return 0, 0
        newest = self.items[-1]
        return newest.stamp, newest.parent

    def latest(self) -> int:
        return self.stamps[-1] if self.stamps else 0

    def oldest(self) -> int:
        return self.stamps[0] if self.stamps else 0

    def __len__(self) -> int:
        return len(self.items)


class StaticCache:
    """A static frame: one transform, valid at every time."""

    def __init__(self) -> None:
        self.item: Stored | None = None

    def insert(self, item: Stored) -> str | None:
        self.item = item
        return None

    def clear(self) -> None:
        """Static transforms survive a clear, as in tf2."""

    def get(self, time_ns: int) -> Stored | str:
        if self.item is None:
            return ""  # tf2 gives no reason
        i = self.item
        return Stored(time_ns, i.parent, i.translation, i.rotation)

    def latest_and_parent(self) -> tuple[int, int]:
        return 0, self.item.parent if self.item is not None else 0

    def latest(self) -> int:
        return 0

    def oldest(self) -> int:
        return 0

    def __len__(self) -> int:
        return 1
