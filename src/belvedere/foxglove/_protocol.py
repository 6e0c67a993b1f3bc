"""Foxglove's WebSocket protocol on the wire: what the server sends, and every client message
read as untrusted input.

The protocol (``foxglove.sdk.v1``, formerly ``foxglove.websocket.v1``) has JSON text frames for
control (``{"op": …}``) and binary frames for data (one opcode byte, then little-endian
fields). :func:`parse_text` and :func:`parse_binary` turn a client's frame into one of the
request types below, or raise :class:`ProtocolError` with the text the client gets back as an
error status: a wrong type, a missing field, an id out of range, too many items, JSON nested
too deep — all are refused here, before anything reaches the graph.
"""

from __future__ import annotations

import json
import math
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Final

__all__ = [
    "MAX_ITEMS",
    "MAX_STRING",
    "SUBPROTOCOLS",
    "ClientAdvertise",
    "ClientChannel",
    "ClientMessage",
    "ClientUnadvertise",
    "GetParameters",
    "ProtocolError",
    "Request",
    "SetParameters",
    "Subscribe",
    "SubscribeParameterUpdates",
    "Unsubscribe",
    "UnsubscribeParameterUpdates",
    "message_data_header",
    "parse_binary",
    "parse_text",
    "text",
    "time_frame",
]

SUBPROTOCOLS: Final = ("foxglove.sdk.v1", "foxglove.websocket.v1")
"""What the server speaks, newest first (the app offers both; the frames are the same)."""

MESSAGE_DATA: Final = 0x01
TIME: Final = 0x02
SERVICE_CALL_REQUEST: Final = 0x02
"""Client binary opcodes: 1 message data, 2 a service call (not served here)."""

MAX_ITEMS: Final = 10_000
"""Entries of one request (subscriptions, channels, parameter names): the app asks for a few
hundred at most."""
MAX_STRING: Final = 4096
"""Characters of a topic, a name, an encoding or a request id."""
MAX_ID: Final = 0xFFFF_FFFF
"""Ids are unsigned 32-bit on the wire (a message data frame carries them as uint32)."""

_DATA_HEAD: Final = struct.Struct("<BIQ")
_TIME_FRAME: Final = struct.Struct("<BQ")
_CLIENT_HEAD: Final = struct.Struct("<BI")


class ProtocolError(Exception):
    """A client message the server refuses; its text goes back to the client as a status."""


# --- what the server sends -----------------------------------------------------------------------
def text(op: str, **fields: Any) -> str:
    """A JSON control frame."""
    return json.dumps({"op": op, **fields}, separators=(",", ":"), allow_nan=False)


def message_data_header(subscription: int, log_time_ns: int) -> bytes:
    """The head of a message data frame (the serialized message follows)."""
    return _DATA_HEAD.pack(MESSAGE_DATA, subscription, log_time_ns)


def time_frame(ns: int) -> bytes:
    return _TIME_FRAME.pack(TIME, ns)


# --- what clients send ---------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class Subscribe:
    subscriptions: tuple[tuple[int, int], ...]
    """(subscription id, channel id) pairs."""


@dataclass(frozen=True, slots=True)
class Unsubscribe:
    ids: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class ClientChannel:
    id: int
    topic: str
    encoding: str
    schema_name: str


@dataclass(frozen=True, slots=True)
class ClientAdvertise:
    channels: tuple[ClientChannel, ...]


@dataclass(frozen=True, slots=True)
class ClientUnadvertise:
    ids: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class GetParameters:
    names: tuple[str, ...]
    """Empty: every parameter."""
    id: str | None


@dataclass(frozen=True, slots=True)
class SetParameters:
    parameters: tuple[tuple[str, Any], ...]
    """(name, value) pairs; a value of None unsets the parameter."""
    id: str | None


@dataclass(frozen=True, slots=True)
class SubscribeParameterUpdates:
    names: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class UnsubscribeParameterUpdates:
    names: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class ClientMessage:
    channel: int
    data: bytes


Request = (
    Subscribe
    | Unsubscribe
    | ClientAdvertise
    | ClientUnadvertise
    | GetParameters
    | SetParameters
    | SubscribeParameterUpdates
    | UnsubscribeParameterUpdates
    | ClientMessage
)

_UNSERVED: Final = frozenset(
    {"subscribeConnectionGraph", "unsubscribeConnectionGraph", "fetchAsset", "callService"}
)


def _no_constant(name: str) -> Any:
    msg = f"invalid message: {name} is not a JSON number"
    raise ProtocolError(msg)


def parse_text(frame: str) -> Request:
    """A client's JSON control frame.

    Raises:
        ProtocolError: it is not one of the requests this server serves, well formed.
    """
    try:
        doc = json.loads(frame, parse_constant=_no_constant)
    except RecursionError:
        msg = "invalid message: JSON nested too deep"
        raise ProtocolError(msg) from None
    except ValueError as err:  # JSONDecodeError, and int() of a 5000-digit number
        msg = f"invalid message: {err}"
        raise ProtocolError(msg) from None
    if not isinstance(doc, dict):
        msg = "invalid message: expected a JSON object with an 'op'"
        raise ProtocolError(msg)
    op = doc.get("op")
    if not isinstance(op, str):
        msg = "invalid message: expected a JSON object with an 'op'"
        raise ProtocolError(msg)
    if op == "subscribe":
        subs = _items(doc, "subscriptions", dict)
        return Subscribe(tuple((_id(s, "id"), _id(s, "channelId")) for s in subs))
    if op == "unsubscribe":
        return Unsubscribe(tuple(_checked_id(i) for i in _items(doc, "subscriptionIds", int)))
    if op == "advertise":
        return ClientAdvertise(tuple(_client_channel(c) for c in _items(doc, "channels", dict)))
    if op == "unadvertise":
        return ClientUnadvertise(tuple(_checked_id(i) for i in _items(doc, "channelIds", int)))
    if op == "getParameters":
        names = tuple(_string(n, "parameterNames") for n in _items(doc, "parameterNames", str))
        return GetParameters(names, _request_id(doc))
    if op == "setParameters":
        params = tuple(_parameter(p) for p in _items(doc, "parameters", dict))
        return SetParameters(params, _request_id(doc))
    if op in ("subscribeParameterUpdates", "unsubscribeParameterUpdates"):
        names = tuple(_string(n, "parameterNames") for n in _items(doc, "parameterNames", str))
        if op == "subscribeParameterUpdates":
            return SubscribeParameterUpdates(names)
        return UnsubscribeParameterUpdates(names)
    shown = op if len(op) <= 64 else op[:61] + "..."
    if op in _UNSERVED:
        msg = f"{shown!r} is not served by this bridge"
    else:
        msg = f"invalid message: unknown op {shown!r}"
    raise ProtocolError(msg)


def parse_binary(frame: bytes) -> ClientMessage:
    """A client's binary frame: only message data (opcode 1) is served.

    Raises:
        ProtocolError: another opcode, or a frame shorter than its fixed fields.
    """
    if not frame:
        msg = "invalid message: an empty binary frame"
        raise ProtocolError(msg)
    if frame[0] == SERVICE_CALL_REQUEST:
        msg = "service calls are not served by this bridge"
        raise ProtocolError(msg)
    if frame[0] != MESSAGE_DATA:
        msg = f"invalid message: unknown binary opcode {frame[0]}"
        raise ProtocolError(msg)
    if len(frame) < _CLIENT_HEAD.size:
        msg = (
            f"invalid message: a message data frame of {len(frame)} bytes "
            f"(its header alone is {_CLIENT_HEAD.size})"
        )
        raise ProtocolError(msg)
    _, channel = _CLIENT_HEAD.unpack_from(frame)
    return ClientMessage(channel, bytes(frame[_CLIENT_HEAD.size :]))


# --- field checks ------------------------------------------------------------------------------
def _items(doc: dict[str, Any], key: str, kind: type) -> Sequence[Any]:
    items = doc.get(key)
    if not isinstance(items, list):
        msg = f"invalid message: {doc['op']} needs a list {key!r}"
        raise ProtocolError(msg)
    if len(items) > MAX_ITEMS:
        msg = f"invalid message: {len(items):,} {key} in one {doc['op']} (at most {MAX_ITEMS:,})"
        raise ProtocolError(msg)
    for item in items:
        if not isinstance(item, kind) or (kind is int and isinstance(item, bool)):
            msg = f"invalid message: {key} holds {_json_kind(item)}, not {_json_kind(kind())}"
            raise ProtocolError(msg)
    return items


def _json_kind(value: Any) -> str:
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int | float):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, dict):
        return "an object"
    return "null"


def _shown(value: Any) -> str:
    """A client's value in a message: short, whatever its size."""
    text = repr(value) if isinstance(value, int | float) else _json_kind(value)
    return text if len(text) <= 24 else f"{text[:12]}…({len(text)} digits)"


def _checked_id(value: int) -> int:
    if not 0 <= value <= MAX_ID:
        msg = f"invalid message: id {_shown(value)} is not an unsigned 32-bit integer"
        raise ProtocolError(msg)
    return value


def _id(obj: dict[str, Any], key: str) -> int:
    value = obj.get(key)
    if not isinstance(value, int) or isinstance(value, bool):
        msg = f"invalid message: {key!r} must be an unsigned 32-bit integer, not {_shown(value)}"
        raise ProtocolError(msg)
    return _checked_id(value)


def _string(value: Any, key: str) -> str:
    if not isinstance(value, str):
        msg = f"invalid message: {key!r} must be a string, not {_json_kind(value)}"
        raise ProtocolError(msg)
    if len(value) > MAX_STRING:
        msg = f"invalid message: {key!r} is {len(value):,} characters (at most {MAX_STRING:,})"
        raise ProtocolError(msg)
    return value


def _request_id(doc: dict[str, Any]) -> str | None:
    value = doc.get("id")
    return None if value is None else _string(value, "id")


def _client_channel(obj: dict[str, Any]) -> ClientChannel:
    return ClientChannel(
        _id(obj, "id"),
        _string(obj.get("topic"), "topic"),
        _string(obj.get("encoding"), "encoding"),
        _string(obj.get("schemaName"), "schemaName"),
    )


def _parameter(obj: dict[str, Any]) -> tuple[str, Any]:
    name = _string(obj.get("name"), "name")
    value = obj.get("value")
    kind = obj.get("type")
    if kind is None:
        return name, value
    if kind == "float64":
        if not isinstance(value, int | float) or isinstance(value, bool):
            msg = f"invalid message: parameter {name!r} of type float64 has {_json_kind(value)}"
            raise ProtocolError(msg)
        return name, _finite(value, name)
    if kind == "float64_array":
        if not isinstance(value, list) or not all(
            isinstance(v, int | float) and not isinstance(v, bool) for v in value
        ):
            msg = f"invalid message: parameter {name!r} of type float64_array is not numbers"
            raise ProtocolError(msg)
        return name, [_finite(v, name) for v in value]
    if kind == "byte_array":
        msg = f"parameter {name!r}: byte arrays are not parameters of this graph"
        raise ProtocolError(msg)
    msg = f"invalid message: parameter {name!r} has an unknown type {str(kind)[:64]!r}"
    raise ProtocolError(msg)


def _finite(value: float, name: str) -> float:
    try:
        number = float(value)
    except OverflowError:
        number = math.inf
    if not math.isfinite(number):
        msg = f"invalid message: parameter {name!r} is not a finite float64"
        raise ProtocolError(msg)
    return number
