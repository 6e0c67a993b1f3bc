"""ROS 1 bytes of a message as parts to send one after another, its large last field not
copied; which messages hold views of the bytes they were read from.

rosbags encodes a string field twice (once to size the buffer, once to fill it) and copies
every field into one new buffer; for a message that ends in a large string (a
``std_msgs/String``) or ``uint8[]`` (an ``Image``, a ``CompressedImage``) that is three
passes over its bulk. Here the message is serialized by rosbags without that field, and the
field's bytes (a string encoded once, an array's own memory) follow it: a socket's
``sendmsg`` takes the parts as they are."""

from __future__ import annotations

import struct
from dataclasses import replace
from typing import Any, Final, cast

import numpy as np
from rosbags.interfaces import Nodetype
from rosbags.typesys.store import Typestore

__all__ = ["BULK_BYTES", "Ros1Parts", "holds_views"]

BULK_BYTES: Final = 4096
"""A last field larger than this is sent as a part of its own (below, one buffer is cheaper
than two parts)."""

_LENGTH: Final = struct.Struct("<I")
_SEQUENCE: Final = int(Nodetype.SEQUENCE)
_BASE: Final = int(Nodetype.BASE)
_NAME: Final = int(Nodetype.NAME)
_ARRAY: Final = int(Nodetype.ARRAY)
_EMPTY_BYTES: Final = np.zeros(0, dtype=np.uint8)


class Ros1Parts:
    """Serialize messages of ``store``'s types to ROS 1 bytes, in parts."""

    def __init__(self, store: Typestore) -> None:
        self.store = store
        self._tails: dict[str, tuple[str, str] | None] = {}
        """type → (its last field, "string" or "uint8[]") when that field can be sent apart"""

    def parts(self, msg: Any, name: str) -> tuple[bytes | memoryview, ...]:
        """``msg``'s ROS 1 bytes (of type ``name``, a store name), as parts whose
        concatenation is what rosbags' ``serialize_ros1`` gives."""
        tails = self._tails
        tail = tails[name] if name in tails else self.tail(name)
        if tail is not None:
            field, kind = tail
            value = getattr(msg, field)
            bulk: bytes | memoryview | None = None
            empty: Any = None
            if kind == "string" and isinstance(value, str) and len(value) > BULK_BYTES:
                bulk, empty = value.encode(), ""
            elif (
                kind == "uint8[]"
                and isinstance(value, np.ndarray)
                and value.dtype == np.uint8
                and value.size > BULK_BYTES
            ):
                bulk, empty = np.ascontiguousarray(value).reshape(-1).data, _EMPTY_BYTES
            if bulk is not None:
                head = self.store.serialize_ros1(replace(msg, **{field: empty}), name)
                # the head ends with the emptied field's length, 0: the real one goes there
                return (bytes(head[:-4]) + _LENGTH.pack(len(bulk)), bulk)
        return (self.store.serialize_ros1(msg, name),)

    def tail(self, name: str) -> tuple[str, str] | None:
        """A type's last field and its kind ("string" or "uint8[]") when it is one of those."""
        if name in self._tails:
            return self._tails[name]
        fields = self.store.fielddefs[name][1]
        tail = None
        if fields:
            field, (kind, detail) = fields[-1]
            if int(kind) == _BASE and detail[0] == "string":
                tail = (field, "string")
            elif int(kind) == _SEQUENCE and detail[0] == (_BASE, ("uint8", 0)):
                tail = (field, "uint8[]")
        self._tails[name] = tail
        return tail


def holds_views(store: Typestore, name: str) -> bool:
    """Whether rosbags' ROS 1 deserializer gives messages of type ``name`` numpy arrays that
    are views of the bytes read (any array or sequence of numbers, at any depth): those
    bytes must then outlive the message."""
    for _, desc in store.fielddefs[name][1]:
        kind, detail = int(desc[0]), cast(Any, desc[1])
        if kind == _NAME and holds_views(store, detail):
            return True
        if kind in (_ARRAY, _SEQUENCE):
            (inner_kind, inner), _ = detail
            if int(inner_kind) == _BASE and inner[0] != "string":
                return True
            if int(inner_kind) == _NAME and holds_views(store, inner):
                return True
    return False
