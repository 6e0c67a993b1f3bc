"""Message and service classes generated from the type store, and the converters between
their instances and the store's (what belvedere's graph publishes and receives).

Each type's class and converters are built once, on first use, from its
:class:`~belvedere.ros1._spec.MessageSpec`; a converter is a chain of precomputed closures, one
per field, so a conversion does no look-ups by name.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from functools import cache
from io import BytesIO
from typing import Any, Final, Protocol

import numpy as np
from rosbags.serde import SerdeError

from belvedere.msgs import NUMPY_DTYPES, PLACEHOLDER, types
from belvedere.ros1._message import DeserializationError, Message
from belvedere.ros1._rostime import Duration, Time
from belvedere.ros1._spec import (
    DURATION,
    TIME,
    FieldSpec,
    MessageSpec,
    message_spec,
    service_md5,
    store_name,
)

__all__ = ["Service", "from_store", "message_class", "service_class", "to_store"]

Convert = Callable[[Any], Any]

_SCALAR_DEFAULTS: Final[dict[str, Any]] = {
    **dict.fromkeys(("byte", "char", "int8", "uint8", "int16", "uint16"), 0),
    **dict.fromkeys(("int32", "uint32", "int64", "uint64"), 0),
    "float32": 0.0,
    "float64": 0.0,
    "string": "",
    "bool": False,
}


class _Writable(Protocol):
    def write(self, data: bytes, /) -> Any: ...


class Service:
    """Base of generated service classes: ``_type``, ``_md5sum``, ``_request_class``,
    ``_response_class`` (as genpy's)."""

    _type: str = ""
    _md5sum: str = ""
    _request_class: type[Message]
    _response_class: type[Message]


# --- classes -----------------------------------------------------------------------------------


def message_class(name: str) -> type[Message]:
    """The genpy-like class of a message type (``geometry_msgs/Twist``,
    ``std_srvs/SetBoolRequest``, or the store's name), built on first use."""
    return _message_class(store_name(name))


@cache
def _message_class(full: str) -> type[Message]:
    spec = message_spec(full)
    pkg, kind, _ = full.split("/")
    class_name = spec.name.split("/")[1]
    namespace: dict[str, Any] = {
        "__slots__": [f.name for f in spec.fields],
        "__module__": f"{pkg}.{kind}",
        "__qualname__": class_name,
        "__doc__": f"``{spec.name}`` (generated from the type store).\n\n{spec.text}",
        "_type": spec.name,
        "_md5sum": spec.md5sum,
        "_full_text": spec.full_text,
        "_has_header": spec.has_header,
        "_slot_types": [f.slot_type for f in spec.fields],
        "_defaults": tuple((f.name, _default_factory(f)) for f in spec.fields),
        "serialize": _serialize,
        "deserialize": _deserialize,
        "_spec": spec,
    }
    for cname, _ctype, value in spec.constants:
        namespace[cname] = value
    cls: type[Message] = type(class_name, (Message,), namespace)
    return cls


def _serialize(self: Message, buff: _Writable) -> None:
    """Write this message in ROS 1 wire format to ``buff`` (a ``BytesIO``)."""
    spec: MessageSpec = self._spec  # type: ignore[attr-defined]
    try:
        obj = _to_store(spec.store_name)(self)
        data = types().store.serialize_ros1(obj, spec.store_name)
    except struct.error as err:
        self._check_types(struct.error(f"{type(err)}: '{err}' when writing '{self}'"))
        raise
    except (TypeError, ValueError, OverflowError) as err:
        self._check_types(ValueError(f"{type(err)}: '{err}' when writing '{self}'"))
        raise
    buff.write(bytes(data))


def _deserialize(self: Message, data: bytes | bytearray | memoryview) -> Message:
    """Fill this message from ROS 1 wire-format bytes; returns it."""
    spec: MessageSpec = self._spec  # type: ignore[attr-defined]
    try:
        obj = types().store.deserialize_ros1(bytes(data), spec.store_name)
    except (SerdeError, struct.error, IndexError, ValueError) as err:
        raise DeserializationError(str(err)) from err
    _fill(spec.store_name)(self, obj)
    return self


def service_class(name: str) -> type[Service]:
    """The genpy-like class of a service type (``std_srvs/SetBool``)."""
    return _service_class(types().resolve_service(name))


@cache
def _service_class(full: str) -> type[Service]:
    pkg, _, base = full.split("/")
    namespace: dict[str, Any] = {
        "__module__": f"{pkg}.srv",
        "__qualname__": base,
        "__doc__": f"``{pkg}/{base}`` (generated from the type store).",
        "_type": f"{pkg}/{base}",
        "_md5sum": service_md5(full),
        "_request_class": _message_class(f"{full}_Request"),
        "_response_class": _message_class(f"{full}_Response"),
    }
    return type(base, (Service,), namespace)


def _default_factory(field: FieldSpec) -> Callable[[], Any]:
    single = _single_default(field)
    if field.array is None:
        return single
    if field.base in ("uint8", "char"):
        raw = b"\0" * field.array
        return lambda: raw
    if field.array == 0:
        return list
    n = field.array
    if field.base in _SCALAR_DEFAULTS:
        value = _SCALAR_DEFAULTS[field.base]
        return lambda: [value] * n
    return lambda: [single() for _ in range(n)]


def _single_default(field: FieldSpec) -> Callable[[], Any]:
    if field.base == "time":
        return Time
    if field.base == "duration":
        return Duration
    if field.is_message:
        base = field.base
        return lambda: _message_class(base)()
    value = _SCALAR_DEFAULTS[field.base]
    return lambda: value


# --- conversion to the store's objects ---------------------------------------------------------


def to_store(msg: Message) -> Any:
    """The store's object (what belvedere's graph publishes) for a generated message."""
    spec: MessageSpec = msg._spec  # type: ignore[attr-defined]
    return _to_store(spec.store_name)(msg)


@cache
def _to_store(full: str) -> Convert:
    spec = message_spec(full)
    make = types().store.types[full]
    fields = tuple((f.name, _field_to_store(f)) for f in spec.fields)
    if not fields:
        empty = make(**{PLACEHOLDER: 0})
        return lambda _msg: empty

    def convert(msg: Any) -> Any:
        return make(*[conv(getattr(msg, name)) for name, conv in fields])

    return convert


def _identity(value: Any) -> Any:
    return value


def _text(value: Any) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, bytes):
        return value.decode()
    # What genpy's generated code runs into: len() of a value that has none (TypeError,
    # reported as a SerializationError), else encode() of a sized non-string.
    len(value)
    msg = f"'{type(value).__name__}' object has no attribute 'encode'"
    raise AttributeError(msg)


def _field_to_store(field: FieldSpec) -> Convert:
    single = _single_to_store(field)
    if field.array is None:
        return single
    dtype = NUMPY_DTYPES.get(field.base)
    if dtype is None:
        return lambda values: [single(v) for v in values]
    if field.base in ("uint8", "char"):

        def octets(values: Any) -> Any:
            if isinstance(values, bytes | bytearray):
                return np.frombuffer(values, dtype=np.uint8)
            if isinstance(values, str):
                return np.frombuffer(values.encode("latin-1"), dtype=np.uint8)
            return np.asarray(values, dtype=np.uint8)

        return octets
    return lambda values: np.asarray(values, dtype=dtype)


def _single_to_store(field: FieldSpec) -> Convert:
    if field.base in ("time", "duration"):
        make = types().store.types[TIME if field.base == "time" else DURATION]
        return lambda t: make(t.secs, t.nsecs)
    if field.is_message:
        return _to_store(field.base)
    if field.base == "string":
        return _text
    if field.base == "bool":
        return _flag
    return _identity


def _flag(value: Any) -> bool:
    """A ``bool`` field's value: what genpy's packing takes (a bool or an integer)."""
    if isinstance(value, bool | int | np.bool_ | np.integer):
        return bool(value)
    msg = f"a bool is required, not {type(value).__name__}"
    raise TypeError(msg)


# --- conversion from the store's objects -------------------------------------------------------


def from_store(obj: Any) -> Message:
    """The generated message for a store object (what belvedere's graph delivers): values as
    genpy's ``deserialize`` leaves them (numeric arrays as tuples, ``uint8[]`` as bytes)."""
    full: str = obj.__msgtype__
    if "/" in full and full.count("/") == 1:
        full = store_name(full)
    msg: Message = _from_store(full)(obj)
    return msg


@cache
def _from_store(full: str) -> Convert:
    cls = _message_class(full)
    fill = _fill(full)
    new = object.__new__

    def convert(obj: Any) -> Any:
        msg = new(cls)
        fill(msg, obj)
        return msg

    return convert


@cache
def _fill(full: str) -> Callable[[Any, Any], None]:
    spec = message_spec(full)
    fields = tuple((f.name, f.ros_name, _field_from_store(f)) for f in spec.fields)
    setter = object.__setattr__

    def fill(msg: Any, obj: Any) -> None:
        for name, ros_name, conv in fields:
            setter(msg, name, conv(getattr(obj, ros_name)))

    return fill


def _field_from_store(field: FieldSpec) -> Convert:
    single = _single_from_store(field)
    if field.array is None:
        return single
    if field.base in ("uint8", "char"):
        return _octets_from_store
    if field.base in NUMPY_DTYPES:
        return _numbers_from_store
    return lambda values: [single(v) for v in values]


def _octets_from_store(values: Any) -> bytes:
    if isinstance(values, np.ndarray):
        return values.tobytes()
    return bytes(values)


def _numbers_from_store(values: Any) -> tuple[Any, ...]:
    if isinstance(values, np.ndarray):
        return tuple(values.tolist())
    return tuple(values)


def _single_from_store(field: FieldSpec) -> Convert:
    if field.base == "time":
        return lambda t: Time(t.sec, t.nanosec)
    if field.base == "duration":
        return lambda t: Duration(t.sec, t.nanosec)
    if field.is_message:
        return _from_store(field.base)
    if field.base == "bool":
        return bool
    return _identity


def serialize_message(msg: Message) -> bytes:
    """A message's ROS 1 wire bytes (what ``msg.serialize(buff)`` writes)."""
    buff = BytesIO()
    msg.serialize(buff)
    return buff.getvalue()
