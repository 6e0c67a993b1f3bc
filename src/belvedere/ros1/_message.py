"""The base of generated message classes, with genpy's constructor rules, equality, YAML-like
``str`` and dynamic type check; and genpy's exceptions."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, ClassVar, Final

import numpy as np
import yaml

from belvedere.errors import BelvedereError
from belvedere.ros1._rostime import Duration, Time, TVal

__all__ = [
    "DeserializationError",
    "Message",
    "MessageException",
    "SerializationError",
    "check_type",
    "strify_message",
]


class MessageException(BelvedereError):  # noqa: N818 (genpy's name, which rospy code catches)
    """A message could not be built, (de)serialized or filled.

    ``str()`` is the bare message, as genpy's (rospy code logs and compares it); the CLI's
    ``error: …`` line comes from :meth:`describe`."""

    def __str__(self) -> str:
        return self.message


class SerializationError(MessageException):
    """A message's field values do not fit its types."""


class DeserializationError(MessageException):
    """Bytes that do not hold a message of the type asked for."""


class Message:
    """Base of the classes :func:`belvedere.ros1.message_class` generates.

    Fields are set positionally (all of them, in definition order) or by keyword (any of them);
    a field left out or given as None takes its default.
    """

    __slots__ = ["_connection_header"]
    _type: ClassVar[str] = ""
    _md5sum: ClassVar[str] = ""
    _full_text: ClassVar[str] = ""
    _has_header: ClassVar[bool] = False
    _slot_types: ClassVar[list[str]] = []
    _defaults: ClassVar[tuple[tuple[str, Callable[[], Any]], ...]] = ()

    def __init__(self, *args: Any, **kwds: Any) -> None:
        slots: list[str] = type(self).__slots__
        if args and kwds:
            msg = "Message constructor may only use args OR keywords, not both"
            raise TypeError(msg)
        if args:
            if len(args) != len(slots):
                msg = f"Invalid number of arguments, args should be {slots!s} args are{args!s}"
                raise TypeError(msg)
            for name, value in zip(slots, args, strict=True):
                setattr(self, name, value)
            for name, default in self._defaults:
                if getattr(self, name) is None:
                    setattr(self, name, default())
            return
        for name in kwds:
            if name not in slots:
                msg = f"{name} is not an attribute of {type(self).__name__}"
                raise AttributeError(msg)
        for name, default in self._defaults:
            value = kwds.get(name)
            setattr(self, name, default() if value is None else value)

    def serialize(self, buff: Any) -> None:
        """Write this message in ROS 1 wire format to ``buff`` (a ``BytesIO``)."""
        raise NotImplementedError

    def deserialize(self, data: bytes) -> Message:
        """Fill this message from ROS 1 wire-format bytes; returns it."""
        raise NotImplementedError

    def _get_types(self) -> list[str]:
        return self._slot_types

    def _check_types(self, exc: Exception | None = None) -> None:
        """Raise :class:`SerializationError` naming the first field whose value does not fit
        its type; else, when ``exc`` is given, one with its text."""
        for name, typ in zip(self.__slots__, self._slot_types, strict=True):
            check_type(name, typ, getattr(self, name))
        if exc is not None:
            raise SerializationError(str(exc))

    def __getstate__(self) -> list[Any]:
        return [getattr(self, name) for name in self.__slots__]

    def __setstate__(self, state: list[Any]) -> None:
        for name, value in zip(self.__slots__, state, strict=False):
            setattr(self, name, value)

    def __str__(self) -> str:
        return strify_message(self)

    __repr__ = __str__

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, type(self)):
            return False
        for name in self.__slots__:
            try:
                mine, theirs = getattr(self, name), getattr(other, name)
            except AttributeError:
                return False
            if type(mine) in (list, tuple) and type(theirs) in (list, tuple):
                if tuple(mine) != tuple(theirs):
                    return False
            elif not mine == theirs:
                return False
        return True

    def __ne__(self, other: object) -> bool:
        return not self == other

    __hash__ = None  # type: ignore[assignment]  # mutable, compared by value (as genpy's)


# --- str ---------------------------------------------------------------------------------------


def strify_message(val: Any, indent: str = "") -> str:
    """A value as genpy prints it (``str(msg)``, ``rostopic echo``): YAML-like, nested
    messages indented by two spaces."""
    kind = type(val)
    if kind in (int, float, bool):
        return str(val)
    if isinstance(val, str):
        if not val:
            return "''"
        return str(yaml.dump(val, default_style='"')).rstrip("\n")
    if isinstance(val, TVal):
        return f"\n{indent}secs: {val.secs}\n{indent}nsecs: {val.nsecs:9d}"
    if kind in (list, tuple):
        return _strify_sequence(val, indent)
    if isinstance(val, Message):
        inner = "  " + indent
        lines = "\n".join(
            f"{indent}{name}: {strify_message(_shown(val, name, typ), inner)}"
            for name, typ in zip(val.__slots__, val._slot_types, strict=True)
        )
        return "\n" + lines if indent else lines
    return str(val)


def _strify_sequence(val: list[Any] | tuple[Any, ...], indent: str) -> str:
    if not val:
        return "[]"
    first = val[0]
    if isinstance(first, str):
        text = str(yaml.dump(val)).rstrip("\n")
        if text.startswith("["):
            return text
        return "\n" + "\n".join(indent + line for line in text.splitlines())
    if type(first) in (int, float, bool):
        return str(list(val))
    item_indent = indent + "  "
    return "\n" + "\n".join(f"{indent}- {strify_message(v, item_indent)}" for v in val)


def _shown(msg: Message, name: str, typ: str) -> Any:
    """A field's value as printed: ``uint8[]`` bytes (or text) as a list of numbers."""
    value = getattr(msg, name)
    if "uint8[" in typ:
        if isinstance(value, str):
            return [ord(c) for c in value]
        if isinstance(value, bytes):
            return list(value)
    return value


# --- dynamic type check (for error messages) ---------------------------------------------------

_WIDTHS: Final = {
    "byte": 8,
    "char": 8,
    "int8": 8,
    "uint8": 8,
    "int16": 16,
    "uint16": 16,
    "int32": 32,
    "uint32": 32,
    "int64": 64,
    "uint64": 64,
}
_SIGNED: Final = ("byte", "int8", "int16", "int32", "int64")
_UNSIGNED: Final = ("char", "uint8", "uint16", "uint32", "uint64")


def check_type(field: str, typ: str, value: Any) -> None:
    """Raise :class:`SerializationError` (with genpy's text) when ``value`` does not fit the
    ROS 1 type ``typ`` of the field ``field``."""
    problem = _type_problem(field, typ, value)
    if problem is not None:
        raise SerializationError(problem)


def _type_problem(field: str, typ: str, value: Any) -> str | None:
    if typ in _SIGNED:
        if type(value) is not int:
            return f"field {field} must be an integer type"
        limit = int(math.pow(2, _WIDTHS[typ] - 1))
        if value >= limit or value < -limit:
            return f"field {field} exceeds specified width [{typ}]"
        return None
    if typ in _UNSIGNED:
        if type(value) is not int or value < 0:
            return f"field {field} must be unsigned integer type"
        if value >= int(math.pow(2, _WIDTHS[typ])):
            return f"field {field} exceeds specified width [{typ}]"
        return None
    if typ in ("float32", "float64"):
        ok = type(value) in (float, int) or isinstance(value, np.floating | np.integer)
        return None if ok else f"field {field} must be float type"
    if typ == "bool":
        return None if value in (True, False, 0, 1) else f"field {field} is not a bool"
    if typ == "string":
        if type(value) is str:
            if not value.isascii():
                return f"field {field} is a non-ascii string"
            return None
        if type(value) is bytes:
            return None
        return f"field {field} must be of type bytes or an ascii string"
    if typ == "time":
        return None if isinstance(value, Time) else f"field {field} must be of type Time"
    if typ == "duration":
        return None if isinstance(value, Duration) else f"field {field} must be of type Duration"
    if typ.endswith("]"):
        base = typ[: typ.index("[")]
        if type(value) in (bytes, str):
            if base not in ("char", "uint8"):
                return f"field {field} must be a list or tuple type. Only uint8[] can be a string"
            return None
        if type(value) not in (list, tuple):
            return f"field {field} must be a list or tuple type"
        for item in value:
            problem = _type_problem(field + "[]", base, item)
            if problem is not None:
                return problem
        return None
    if not isinstance(value, Message):
        return f"field {field} must be of type [{typ}]"
    if value._type in ("std_msgs/Header", "roslib/Header"):
        if typ not in ("Header", "std_msgs/Header", "roslib/Header"):
            return f"field {field} must be a Header instead of a {value._type}"
    elif value._type != typ:
        return f"field {field} must be of type {typ} instead of {value._type}"
    for name, sub in zip(value.__slots__, value._get_types(), strict=True):
        problem = _type_problem(f"{field}.{name}", sub, getattr(value, name))
        if problem is not None:
            return problem
    return None
