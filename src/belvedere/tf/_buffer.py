"""The TF buffer: the frame tree over time, as tf2's ``BufferCore`` keeps it.

Its lookups give what tf2 gives — the same walk up the tree, the same "latest common time" for
time 0, the same interpolation and extrapolation rules, the same checks on incoming transforms
and the same error texts (checked against Debian's tf2 in tests/ros1/test_tf2_ros.py) — so
``tf2_ros`` and ``tf`` for rospy scripts are thin layers over it. belvedere's own parts (the
viewer, ``belvedere tf``) use the :class:`Transform` methods; rospy's layers the
tf2-level ones (:meth:`TFBuffer.lookup`, :meth:`TFBuffer.can`, …).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from typing import Any, Final

from belvedere.tf._cache import (
    NS,
    Quat,
    StaticCache,
    Stored,
    TimeCache,
    Vec3,
    compose,
    conjugate,
    rotate,
    seconds,
)
from belvedere.tf._errors import (
    TFConnectivityError,
    TFError,
    TFExtrapolationError,
    TFInvalidArgumentError,
    TFLookupError,
)
from belvedere.tf._listing import _FrameListings
from belvedere.tf._math import Transform

__all__ = ["TFBuffer", "Transformed"]

MAX_GRAPH_DEPTH: Final = 1000
QUATERNION_TOLERANCE: Final = 10e-3
NO_PARENT: Final = "NO_PARENT"
_IDENTITY_T: Final[Vec3] = (0.0, 0.0, 0.0)
_IDENTITY_Q: Final[Quat] = (0.0, 0.0, 0.0, 1.0)

Transformed = tuple[int, Vec3, Quat]
"""A lookup's result: the stamp (ns), translation and ``quat_xyzw``."""

Log = Callable[[str, str], None]
"""Where tf2's console messages go: ``(level, text)``, level ``"Error"`` or ``"Warning"``."""


def _quiet(level: str, text: str) -> None:
    del level, text


class TFBuffer(_FrameListings):
    """Frames numbered in order of appearance, each child with a cache of its transforms to
    its parent(s) over the last ``cache_time`` seconds (10, as tf2's default)."""

    def __init__(
        self, *, cache_time: float = 10.0, cache_ns: int | None = None, log: Log | None = None
    ) -> None:
        self.cache_ns = round(cache_time * NS) if cache_ns is None else cache_ns
        self.log: Log = log or _quiet
        self._names: list[str] = [NO_PARENT]
        self._ids: dict[str, int] = {}
        self._caches: list[TimeCache | StaticCache | None] = [None]
        self._authority: dict[int, str] = {}

    # --- storing -------------------------------------------------------------------------------
    def _number(self, name: str) -> int:
        number = self._ids.get(name)
        if number is None:
            number = self._ids[name] = len(self._names)
            self._names.append(name)
            self._caches.append(None)
        return number

    def insert(
        self,
        parent: str,
        child: str,
        translation: Vec3,
        rotation: Quat,
        stamp_ns: int,
        *,
        authority: str = "default_authority",
        static: bool = False,
    ) -> bool:
        """Store one transform as tf2's ``setTransform`` does (leading ``/`` stripped), or log
        why not and return False."""
        parent, child = _strip(parent), _strip(child)
        errors: list[str] = []
        if child == parent:
            errors.append(
                f'TF_SELF_TRANSFORM: Ignoring transform from authority "{authority}" with '
                f'frame_id and child_frame_id  "{child}" because they are the same'
            )
        if not child:
            errors.append(
                f'TF_NO_CHILD_FRAME_ID: Ignoring transform from authority "{authority}" '
                "because child_frame_id not set "
            )
        if not parent:
            errors.append(
                f'TF_NO_FRAME_ID: Ignoring transform with child_frame_id "{child}"  from '
                f'authority "{authority}" because frame_id not set'
            )
        if any(math.isnan(v) for v in (*translation, *rotation)):
            errors.append(
                f'TF_NAN_INPUT: Ignoring transform for child_frame_id "{child}" from authority '
                f'"{authority}" because of a nan value in the transform '
                f"({_floats(translation)}) ({_floats(rotation)})"
            )
        x, y, z, w = rotation
        if not abs((w * w + x * x + y * y + z * z) - 1.0) < QUATERNION_TOLERANCE:
            errors.append(
                f'TF_DENORMALIZED_QUATERNION: Ignoring transform for child_frame_id "{child}" '
                f'from authority "{authority}" because of an invalid quaternion in the '
                f"transform ({_floats(rotation)})"
            )
        for text in errors:
            self.log("Error", text)
        if errors:
            return False
        number = self._number(child)
        cache = self._caches[number]
        if cache is None:
            cache = self._caches[number] = StaticCache() if static else TimeCache(self.cache_ns)
        refused = cache.insert(Stored(stamp_ns, self._number(parent), translation, rotation))
        if refused is not None:
            self.log(
                "Warning",
                f"{refused} for frame {child} at time {seconds(stamp_ns):f} "
                f"according to authority {authority}",
            )
            return False
        self._authority[number] = authority
        return True

    def clear(self) -> None:
        """Forget every transform but the static ones (the frames stay known)."""
        for cache in self._caches:
            if cache is not None:
                cache.clear()

    # --- tf2's queries ---------------------------------------------------------------------------
    def validate(self, function: str, frame: str) -> int:
        """The number of ``frame``, or tf2's error for ``function``'s argument."""
        if not frame:
            msg = f"Invalid argument passed to {function} in tf2 frame_ids cannot be empty"
            raise TFInvalidArgumentError(msg)
        if frame.startswith("/"):
            msg = (
                f'Invalid argument "{frame}" passed to {function} in tf2 frame_ids cannot start '
                "with a '/' like: "
            )
            raise TFInvalidArgumentError(msg)
        number = self._ids.get(frame, 0)
        if number == 0:
            msg = f'"{frame}" passed to {function} does not exist. '
            raise TFLookupError(msg)
        return number

    def _warn_invalid(self, function: str, frame: str) -> bool:
        """tf2's ``canTransform`` only warns about a bad frame name (and answers no)."""
        try:
            if not frame or frame.startswith("/"):
                self.validate(function, frame)
        except TFInvalidArgumentError as err:
            self.log("Warning", err.message)
            return True
        return False

    def lookup(self, target: str, source: str, time_ns: int) -> Transformed:
        """tf2's ``lookupTransform``: ``T_target_source`` at ``time_ns`` (0: the latest time
        the frames between share) and the time it holds for."""
        if target == source:
            if time_ns == 0:
                cache = self._caches[self._ids.get(target, 0)]
                time_ns = cache.latest() if cache is not None else 0
            return time_ns, _IDENTITY_T, _IDENTITY_Q
        target_id = self.validate("lookupTransform argument target_frame", target)
        source_id = self.validate("lookupTransform argument source_frame", source)
        return self._walk(time_ns, target_id, source_id)

    def lookup_full(
        self, target: str, target_ns: int, source: str, source_ns: int, fixed: str
    ) -> Transformed:
        """tf2's advanced ``lookupTransform``: ``source`` at ``source_ns`` into ``fixed``,
        held still there, then into ``target`` at ``target_ns``."""
        self.validate("lookupTransform argument target_frame", target)
        self.validate("lookupTransform argument source_frame", source)
        self.validate("lookupTransform argument fixed_frame", fixed)
        _, t1, q1 = self.lookup(fixed, source, source_ns)
        stamp, t2, q2 = self.lookup(target, fixed, target_ns)
        t, q = _matrix_compose(t2, q2, t1, q1)
        return stamp, t, q

    def can(self, target: str, source: str, time_ns: int) -> tuple[bool, str]:
        """tf2's ``canTransform``: whether :meth:`lookup` would succeed, and why not."""
        if target == source:
            return True, ""
        if self._warn_invalid("canTransform argument target_frame", target):
            return False, ""
        if self._warn_invalid("canTransform argument source_frame", source):
            return False, ""
        target_id, source_id = self._ids.get(target, 0), self._ids.get(source, 0)
        missing: list[str] = []
        if target_id == 0:
            missing.append(f"canTransform: target_frame {target} does not exist.")
        if source_id == 0:
            missing.append(f"canTransform: source_frame {source} does not exist.")
        if missing:
            return False, " ".join(missing)
        return self._can(target_id, source_id, time_ns)

    def can_full(
        self, target: str, target_ns: int, source: str, source_ns: int, fixed: str
    ) -> tuple[bool, str]:
        """tf2's advanced ``canTransform``."""
        for argument, frame in (("target", target), ("source", source), ("fixed", fixed)):
            if self._warn_invalid(f"canTransform argument {argument}_frame", frame):
                return False, ""
        target_id, source_id = self._ids.get(target, 0), self._ids.get(source, 0)
        fixed_id = self._ids.get(fixed, 0)
        if 0 in (target_id, source_id, fixed_id):
            missing: list[str] = []
            if target_id == 0:
                missing.append(f"canTransform: target_frame {target} does not exist.")
            if source_id == 0:
                # tf2 reports the fixed frame here, only when the source is missing, and
                # without a space before "does"
                missing.append(f"canTransform: source_frame {source} does not exist.")
                missing.append(f"fixed_frame: {fixed}does not exist.")
            return False, " ".join(missing)
        ok, why = self._can(target_id, fixed_id, target_ns)
        if not ok:
            return ok, why
        return self._can(fixed_id, source_id, source_ns)

    def _can(self, target_id: int, source_id: int, time_ns: int) -> tuple[bool, str]:
        if target_id == source_id:
            return True, ""
        try:
            self._walk(time_ns, target_id, source_id)
        except TFError as err:
            return False, err.message
        return True, ""

    def latest_common_time(self, target: str, source: str) -> int:
        """The latest time (ns) at which ``source`` can be transformed into ``target`` (0 when
        only static transforms join them), as tf2's python ``get_latest_common_time``."""
        target_id = self.validate("get_latest_common_time", target)
        source_id = self.validate("get_latest_common_time", source)
        try:
            return self._latest_common(target_id, source_id)
        except TFError as err:
            # tf2's binding raises these as its base TransformException
            raise TFError(err.message) from None

    # --- the walk --------------------------------------------------------------------------------
    def _loop_error(self) -> TFLookupError:
        text = (
            "The tf tree is invalid because it contains a loop.\n"
            + self.all_frames_as_string()
            + "\n"
        )
        return TFLookupError(text)

    def _connectivity_error(self, source_id: int, target_id: int) -> TFConnectivityError:
        return TFConnectivityError(
            f"Could not find a connection between '{self._names[target_id]}' and "
            f"'{self._names[source_id]}' because they are not part of the same tree."
            "Tf has two or more unconnected trees."
        )

    def _latest_common(self, target_id: int, source_id: int) -> int:
        """tf2's ``getLatestCommonTime``: the earliest of the latest stamps along the path
        (static transforms, stamped 0, left out), or 0."""
        if source_id == target_id:
            cache = self._caches[source_id]
            return cache.latest() if cache is not None else 0
        forever = 1 << 64
        up_from_source: list[tuple[int, int]] = []
        common = forever
        for stamp, parent in self._latest_up(source_id):
            if stamp:
                common = min(common, stamp)
            up_from_source.append((stamp, parent))
            if parent == target_id:
                return 0 if common == forever else common
        parents = [p for _, p in up_from_source]
        common, meeting = forever, 0
        for stamp, parent in self._latest_up(target_id):
            if stamp:
                common = min(common, stamp)
            if parent in parents:
                meeting = parent
                break
            if parent == source_id:
                return 0 if common == forever else common
        if meeting == 0:
            raise self._connectivity_error(source_id, target_id)
        for stamp, parent in up_from_source:
            if stamp:
                common = min(common, stamp)
            if parent == meeting:
                break
        return 0 if common == forever else common

    def _latest_up(self, frame: int) -> Iterator[tuple[int, int]]:
        """Up the tree from ``frame`` as far as data goes: each step's latest stamp and the
        parent it leads to.

        Raises:
            TFLookupError: more than MAX_GRAPH_DEPTH steps (a loop).
        """
        depth = 0
        while frame != 0:
            cache = self._caches[frame]
            if cache is None:
                return
            stamp, parent = cache.latest_and_parent()
            if parent == 0:
                return
            yield stamp, parent
            frame = parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()

    def _walk(self, time_ns: int, target_id: int, source_id: int) -> Transformed:
        """tf2's ``walkToTopParent``: up from the source as far as data goes, then up from
        the target until the two walks meet."""
        if source_id == target_id:
            return time_ns, _IDENTITY_T, _IDENTITY_Q
        if time_ns == 0:
            time_ns = self._latest_common(target_id, source_id)
        source_t, source_q = _IDENTITY_T, _IDENTITY_Q
        frame = top = source_id
        depth = 0
        source_gap: str | None = None
        while frame != 0:
            cache = self._caches[frame]
            if cache is None:
                top = frame
                break
            got = cache.get(time_ns)
            if isinstance(got, str):
                # there may still be a path from the target up to here
                top, source_gap = frame, got
                break
            if frame == target_id:
                return time_ns, source_t, source_q
            source_t, source_q = compose(got.translation, got.rotation, source_t, source_q)
            top, frame = frame, got.parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()
        where = (
            f", when looking up transform from frame [{self._names[source_id]}] to frame "
            f"[{self._names[target_id]}]"
        )
        target_t, target_q = _IDENTITY_T, _IDENTITY_Q
        frame, depth = target_id, 0
        while frame != top:
            cache = self._caches[frame]
            if cache is None:
                break
            got = cache.get(time_ns)
            if isinstance(got, str):
                raise TFExtrapolationError(got + where)
            if frame == source_id:
                inverse_q = conjugate(target_q)
                return time_ns, _neg(rotate(inverse_q, target_t)), inverse_q
            target_t, target_q = compose(got.translation, got.rotation, target_t, target_q)
            frame = got.parent
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                raise self._loop_error()
        if frame != top:
            if source_gap is not None:
                raise TFExtrapolationError(source_gap + where)
            raise self._connectivity_error(source_id, target_id)
        inverse_q = conjugate(target_q)
        inverse_t = _neg(rotate(inverse_q, target_t))
        t, q = compose(inverse_t, inverse_q, source_t, source_q)
        return time_ns, t, q

    # --- belvedere's interface ---------------------------------------------------------------
    def set_transform(
        self, parent: str, child: str, transform: Transform, stamp_ns: int, *, static: bool = False
    ) -> None:
        """Store ``T_parent_child`` at ``stamp_ns``; a transform tf2 refuses outright (a frame
        its own parent, an empty name, NaN, a quaternion not of length 1) raises."""
        problems: list[str] = []

        def keep(level: str, text: str) -> None:
            if level == "Error":
                problems.append(text)
            else:
                log(level, text)  # the buffer's own log: self.log is this function meanwhile

        log, self.log = self.log, keep
        (tx, ty, tz), (qx, qy, qz, qw) = transform.translation, transform.quat_xyzw
        try:
            self.insert(
                parent,
                child,
                (float(tx), float(ty), float(tz)),
                (float(qx), float(qy), float(qz), float(qw)),
                stamp_ns,
                static=static,
            )
        finally:
            self.log = log
        if problems:
            raise TFError("; ".join(problems))

    def set_message(self, msg: Any, *, static: bool = False, authority: str = "") -> None:
        """Add a ``tf2_msgs/TFMessage`` (or one ``TransformStamped``) of the store; the
        transforms tf2 would refuse are logged and skipped."""
        items = msg.transforms if hasattr(msg, "transforms") else [msg]
        for t in items:
            tr, rot = t.transform.translation, t.transform.rotation
            self.insert(
                t.header.frame_id,
                t.child_frame_id,
                (tr.x, tr.y, tr.z),
                (rot.x, rot.y, rot.z, rot.w),
                t.header.stamp.sec * NS + t.header.stamp.nanosec,
                authority=authority or "default_authority",
                static=static,
            )

    def frames(self) -> set[str]:
        return set(self._names[1:])

    def parent(self, frame: str) -> str | None:
        number = self._ids.get(_strip(frame), 0)
        parent = self._parent_now(number) if number else None
        return self._names[parent] if parent else None

    def lookup_transform(self, target: str, source: str, time_ns: int = 0) -> Transform:
        """``T_target_source`` at ``time_ns`` (0: the latest time all frames share); leading
        ``/`` are ignored."""
        try:
            _, t, q = self.lookup(_strip(target), _strip(source), time_ns)
        except TFLookupError as err:
            if err.message.endswith("does not exist. "):
                known = ", ".join(sorted(self.frames())) or "none yet"
                raise TFLookupError(err.message, hint=f"the frames known: {known}") from None
            raise
        return Transform(t, q)

    def can_transform(self, target: str, source: str, time_ns: int = 0) -> bool:
        try:
            self.lookup_transform(target, source, time_ns)
        except TFError:
            return False
        return True


def _strip(frame: str) -> str:
    return frame[1:] if frame.startswith("/") else frame


def _neg(v: Vec3) -> Vec3:
    return (-v[0], -v[1], -v[2])


def _floats(values: tuple[float, ...]) -> str:
    return " ".join(f"{v:f}" for v in values)


def _basis(q: Quat) -> list[list[float]]:
    """tf2's ``Matrix3x3::setRotation`` (normalising)."""
    x, y, z, w = q
    s = 2.0 / (x * x + y * y + z * z + w * w)
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    return [
        [1.0 - (yy + zz), xy - wz, xz + wy],
        [xy + wz, 1.0 - (xx + zz), yz - wx],
        [xz - wy, yz + wx, 1.0 - (xx + yy)],
    ]


def _rotation(m: list[list[float]]) -> Quat:
    """tf2's ``Matrix3x3::getRotation``."""
    trace = m[0][0] + m[1][1] + m[2][2]
    q = [0.0, 0.0, 0.0, 0.0]
    if trace > 0.0:
        s = math.sqrt(trace + 1.0)
        q[3] = s * 0.5
        s = 0.5 / s
        q[0] = (m[2][1] - m[1][2]) * s
        q[1] = (m[0][2] - m[2][0]) * s
        q[2] = (m[1][0] - m[0][1]) * s
    else:
        # the largest diagonal entry (the first of equal ones)
        diagonal = (m[0][0], m[1][1], m[2][2])
        i = diagonal.index(max(diagonal))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = math.sqrt(m[i][i] - m[j][j] - m[k][k] + 1.0)
        q[i] = s * 0.5
        s = 0.5 / s
        q[3] = (m[k][j] - m[j][k]) * s
        q[j] = (m[j][i] + m[i][j]) * s
        q[k] = (m[k][i] + m[i][k]) * s
    return (q[0], q[1], q[2], q[3])


def _matrix_compose(t2: Vec3, q2: Quat, t1: Vec3, q1: Quat) -> tuple[Vec3, Quat]:
    """``tf2::Transform(q2, t2) * tf2::Transform(q1, t1)``, through rotation matrices as tf2
    multiplies them."""
    a, b = _basis(q2), _basis(q1)
    product = [[sum(a[r][k] * b[k][c] for k in range(3)) for c in range(3)] for r in range(3)]
    t = tuple(a[r][0] * t1[0] + a[r][1] * t1[1] + a[r][2] * t1[2] + t2[r] for r in range(3))
    return (t[0], t[1], t[2]), _rotation(product)
