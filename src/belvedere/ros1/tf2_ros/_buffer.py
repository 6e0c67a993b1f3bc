"""tf2_ros's ``Buffer``: tf2's ``BufferCore`` (belvedere's :class:`~belvedere.tf.TFBuffer`)
with rospy's times and messages, tf2_ros's waiting, and ``transform()`` for the message types a
``tf2_*`` module registered (``tf2_geometry_msgs``)."""

from __future__ import annotations

import math
import sys
import threading
from collections.abc import Callable
from copy import deepcopy
from typing import Any, ClassVar, Final

from belvedere.graph import NS
from belvedere.ros1 import message_class, rospy
from belvedere.ros1.tf2_ros._exceptions import (
    NotImplementedException,
    TypeException,
    translated,
)
from belvedere.tf import TFBuffer, TFError, Transformed
from belvedere.tf._cache import seconds

__all__ = [
    "Buffer",
    "BufferCore",
    "BufferInterface",
    "ConvertRegistration",
    "Stamped",
    "TransformRegistration",
    "convert",
    "duration_ns",
    "stamp_ns",
]

DEFAULT_CAN_TRANSFORM_POLLING_SCALE: Final = 0.01
DEFAULT_CACHE_NS: Final = 10 * NS


def stamp_ns(value: Any) -> int:
    """A time as tf2's binding reads it: ``to_sec()``, then ``ros::Time::fromSec`` (rounded
    to the nearest nanosecond, halves away from zero)."""
    to_sec = getattr(value, "to_sec", None)
    if to_sec is None:
        msg = "time must have a to_sec method, e.g. rospy.Time or rospy.Duration"
        raise TypeError(msg)
    t = float(to_sec())
    whole = math.floor(t)
    return whole * NS + math.floor((t - whole) * 1e9 + 0.5)


duration_ns = stamp_ns


def _console(level: str, text: str) -> None:
    """tf2 writes its warnings with console_bridge, to stderr."""
    sys.stderr.write(f"{level + ':':<8} {text}\n")


def _time(ns: int) -> rospy.Time:
    return rospy.Time(ns // NS, ns % NS)


class BufferCore:
    """tf2's ``BufferCore`` as its python binding offers it."""

    def __init__(self, cache_time: Any = None) -> None:
        cache_ns = DEFAULT_CACHE_NS if cache_time is None else duration_ns(cache_time)
        self._core = TFBuffer(cache_ns=cache_ns, log=_console)
        self._lock = threading.RLock()  # listeners fill the buffer from their own threads

    def _call(self, fn: Callable[..., Any], *args: Any) -> Any:
        with self._lock:
            try:
                return fn(*args)
            except TFError as err:
                raise translated(err) from None

    def _message(self, result: Transformed, target: str, source: str) -> Any:
        stamp, (tx, ty, tz), (qx, qy, qz, qw) = result
        msg: Any = message_class("geometry_msgs/TransformStamped")()
        msg.header.stamp = _time(stamp)
        msg.header.frame_id = target
        msg.child_frame_id = source
        t, r = msg.transform.translation, msg.transform.rotation
        t.x, t.y, t.z = tx, ty, tz
        r.x, r.y, r.z, r.w = qx, qy, qz, qw
        return msg

    def _set(self, transform: Any, authority: str, static: bool) -> None:
        header = transform.header
        stamp = stamp_ns(header.stamp)
        t, r = transform.transform.translation, transform.transform.rotation
        with self._lock:
            self._core.insert(
                str(header.frame_id),
                str(transform.child_frame_id),
                (float(t.x), float(t.y), float(t.z)),
                (float(r.x), float(r.y), float(r.z), float(r.w)),
                stamp,
                authority=authority,
                static=static,
            )

    def set_transform(self, transform: Any, authority: str) -> None:
        self._set(transform, authority, static=False)

    def set_transform_static(self, transform: Any, authority: str) -> None:
        self._set(transform, authority, static=True)

    def lookup_transform_core(self, target_frame: str, source_frame: str, time: Any) -> Any:
        result = self._call(self._core.lookup, target_frame, source_frame, stamp_ns(time))
        return self._message(result, target_frame, source_frame)

    def lookup_transform_full_core(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
    ) -> Any:
        result = self._call(
            self._core.lookup_full,
            target_frame,
            stamp_ns(target_time),
            source_frame,
            stamp_ns(source_time),
            fixed_frame,
        )
        return self._message(result, target_frame, source_frame)

    def can_transform_core(
        self, target_frame: str, source_frame: str, time: Any
    ) -> tuple[int, str]:
        ok, why = self._call(self._core.can, target_frame, source_frame, stamp_ns(time))
        return int(ok), why

    def can_transform_full_core(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
    ) -> tuple[int, str]:
        ok, why = self._call(
            self._core.can_full,
            target_frame,
            stamp_ns(target_time),
            source_frame,
            stamp_ns(source_time),
            fixed_frame,
        )
        return int(ok), why

    def get_latest_common_time(self, target_frame: str, source_frame: str) -> rospy.Time:
        return _time(self._call(self._core.latest_common_time, target_frame, source_frame))

    def all_frames_as_yaml(self) -> str:
        text: str = self._call(self._core.all_frames_as_yaml)
        return text

    def all_frames_as_string(self) -> str:
        text: str = self._call(self._core.all_frames_as_string)
        return text

    def _allFramesAsDot(self, time: Any = None) -> str:  # noqa: N802 (tf2's name)
        """The tree for Graphviz; with ``time`` (a ``rospy.Time``), each transform's age."""
        now = 0.0 if time is None else seconds(stamp_ns(time))
        text: str = self._call(self._core.all_frames_as_dot, now)
        return text

    def _frameExists(self, frame_id: str) -> bool:  # noqa: N802 (tf2's name)
        with self._lock:
            return self._core.frame_exists(frame_id)

    def _getFrameStrings(self) -> list[str]:  # noqa: N802 (tf2's name)
        with self._lock:
            return self._core.frame_strings()

    def clear(self) -> None:
        with self._lock:
            self._core.clear()


class TransformRegistration:
    """Which function transforms which message type (filled by ``tf2_geometry_msgs``)."""

    _map: ClassVar[dict[Any, Callable[[Any, Any], Any]]] = {}

    def add(self, key: Any, callback: Callable[[Any, Any], Any]) -> None:
        TransformRegistration._map[key] = callback

    def get(self, key: Any) -> Callable[[Any, Any], Any]:
        if key not in TransformRegistration._map:
            msg = f"Type {key} if not loaded or supported"
            raise TypeException(msg)
        return TransformRegistration._map[key]

    def print_me(self) -> None:
        sys.stdout.write(f"{TransformRegistration._map}\n")


class ConvertRegistration:
    """Conversions between message types and others (filled by ``tf2_*`` modules)."""

    _to_msg: ClassVar[dict[Any, Callable[[Any], Any]]] = {}
    _from_msg: ClassVar[dict[Any, Callable[[Any], Any]]] = {}
    _convert: ClassVar[dict[Any, Callable[[Any], Any]]] = {}

    def add_from_msg(self, key: Any, callback: Callable[[Any], Any]) -> None:
        ConvertRegistration._from_msg[key] = callback

    def add_to_msg(self, key: Any, callback: Callable[[Any], Any]) -> None:
        ConvertRegistration._to_msg[key] = callback

    def add_convert(self, key: Any, callback: Callable[[Any], Any]) -> None:
        ConvertRegistration._convert[key] = callback

    @staticmethod
    def _get(table: dict[Any, Callable[[Any], Any]], key: Any) -> Callable[[Any], Any]:
        if key not in table:
            msg = f"Type {key} if not loaded or supported"
            raise TypeException(msg)
        return table[key]

    def get_from_msg(self, key: Any) -> Callable[[Any], Any]:
        return self._get(ConvertRegistration._from_msg, key)

    def get_to_msg(self, key: Any) -> Callable[[Any], Any]:
        return self._get(ConvertRegistration._to_msg, key)

    def get_convert(self, key: Any) -> Callable[[Any], Any]:
        return self._get(ConvertRegistration._convert, key)


def convert(a: Any, b_type: Any) -> Any:
    """``a`` as a ``b_type``: a direct conversion, a copy, or through the message type."""
    registry = ConvertRegistration()
    try:
        return registry.get_convert((type(a), b_type))(a)
    except TypeException:
        if type(a) is b_type:
            return deepcopy(a)
        return registry.get_from_msg(b_type)(registry.get_to_msg(type(a))(a))


def Stamped(obj: Any, stamp: Any, frame_id: str) -> Any:  # noqa: N802 (tf2_ros's name)
    """``obj`` with a header of ``stamp`` and ``frame_id``."""
    obj.header = message_class("std_msgs/Header")(frame_id=frame_id, stamp=stamp)
    return obj


class BufferInterface:
    """tf2_ros's buffer interface: ``transform()`` over ``lookup_transform``."""

    def __init__(self) -> None:
        self.registration = TransformRegistration()

    def transform(
        self,
        object_stamped: Any,
        target_frame: str,
        timeout: Any = None,
        new_type: Any = None,
    ) -> Any:
        """``object_stamped`` (a type a ``tf2_*`` module registered) in ``target_frame``."""
        return self._transformed(
            object_stamped,
            lambda header: self.lookup_transform(
                target_frame, header.frame_id, header.stamp, _zero(timeout)
            ),
            new_type,
        )

    def transform_full(
        self,
        object_stamped: Any,
        target_frame: str,
        target_time: Any,
        fixed_frame: str,
        timeout: Any = None,
        new_type: Any = None,
    ) -> Any:
        """As :meth:`transform`, into ``target_frame`` at ``target_time`` via ``fixed_frame``."""
        return self._transformed(
            object_stamped,
            lambda header: self.lookup_transform_full(
                target_frame,
                target_time,
                header.frame_id,
                header.stamp,
                fixed_frame,
                _zero(timeout),
            ),
            new_type,
        )

    def _transformed(self, object_stamped: Any, lookup: Callable[[Any], Any], new_type: Any) -> Any:
        """``object_stamped`` moved by the transform ``lookup`` finds for its header; its
        type is checked first, as tf2_ros does, so an unregistered one looks nothing up."""
        do_transform = self.registration.get(type(object_stamped))
        result = do_transform(object_stamped, lookup(object_stamped.header))
        return result if not new_type else convert(result, new_type)

    def lookup_transform(
        self, target_frame: str, source_frame: str, time: Any, timeout: Any = None
    ) -> Any:
        raise NotImplementedException

    def lookup_transform_full(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
        timeout: Any = None,
    ) -> Any:
        raise NotImplementedException

    def can_transform(
        self, target_frame: str, source_frame: str, time: Any, timeout: Any = None
    ) -> Any:
        raise NotImplementedException

    def can_transform_full(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
        timeout: Any = None,
    ) -> Any:
        raise NotImplementedException


def _zero(timeout: Any) -> Any:
    return rospy.Duration(0.0) if timeout is None else timeout


class Buffer(BufferCore, BufferInterface):
    """tf2_ros.Buffer: transforms to look up, ``cache_time`` (a ``rospy.Duration``, 10 s by
    default) of history kept. ``debug`` is accepted; its ``~tf2_frames`` service is not
    offered."""

    def __init__(self, cache_time: Any = None, debug: bool = True) -> None:
        BufferCore.__init__(self, cache_time)
        BufferInterface.__init__(self)
        del debug
        self.CAN_TRANSFORM_POLLING_SCALE = DEFAULT_CAN_TRANSFORM_POLLING_SCALE

    def _wait(self, timeout: Any, ready: Callable[[], bool]) -> None:
        """tf2_ros's polling: until ``ready()``, ``timeout`` (ROS time) passes, or time jumps
        back more than 3 s (a bag loop)."""
        if timeout == rospy.Duration(0.0):
            return
        start = rospy.Time.now()
        interval = timeout * self.CAN_TRANSFORM_POLLING_SCALE
        while (
            rospy.Time.now() < start + timeout
            and not ready()
            and rospy.Time.now() + rospy.Duration(3.0) >= start
        ):
            rospy.sleep(interval)

    def lookup_transform(
        self, target_frame: str, source_frame: str, time: Any, timeout: Any = None
    ) -> Any:
        """``T_target_source`` at ``time`` (``rospy.Time(0)``: the latest), as a
        ``geometry_msgs/TransformStamped``, waiting up to ``timeout`` for it."""
        self.can_transform(target_frame, source_frame, time, _zero(timeout))
        return self.lookup_transform_core(target_frame, source_frame, time)

    def lookup_transform_full(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
        timeout: Any = None,
    ) -> Any:
        self.can_transform_full(
            target_frame, target_time, source_frame, source_time, fixed_frame, _zero(timeout)
        )
        return self.lookup_transform_full_core(
            target_frame, target_time, source_frame, source_time, fixed_frame
        )

    def can_transform(
        self,
        target_frame: str,
        source_frame: str,
        time: Any,
        timeout: Any = None,
        return_debug_tuple: bool = False,
    ) -> Any:
        """Whether the transform can be looked up (waiting up to ``timeout``): ``1``/``0``, or
        with ``return_debug_tuple`` the reason too."""
        self._wait(
            _zero(timeout),
            lambda: bool(self.can_transform_core(target_frame, source_frame, time)[0]),
        )
        result = self.can_transform_core(target_frame, source_frame, time)
        return result if return_debug_tuple else result[0]

    def can_transform_full(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
        timeout: Any = None,
        return_debug_tuple: bool = False,
    ) -> Any:
        def core() -> tuple[int, str]:
            return self.can_transform_full_core(
                target_frame, target_time, source_frame, source_time, fixed_frame
            )

        self._wait(_zero(timeout), lambda: bool(core()[0]))
        result = core()
        return result if return_debug_tuple else result[0]
