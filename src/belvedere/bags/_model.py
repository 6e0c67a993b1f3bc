"""What every bag format shares: connections, messages, errors, and the message types.

A connection is one topic as one publisher offered it: its type (the store's spelling,
``pkg/msg/Type``), how its messages are encoded (``ros1``: ROS 1's wire format, as ROS 1
bags hold it; ``cdr``: as belvedere's transport and ROS 2 carry it), the type's definition
and MD5 sum, and whether it latched.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from functools import cache
from typing import Any, NamedTuple

from rosbags.typesys import TypesysError, get_types_from_msg

from belvedere.errors import BelvedereError
from belvedere.msgs import MessageTypeError, short, types

__all__ = [
    "BagError",
    "BagMessage",
    "Connection",
    "Decoder",
    "cdr_schema",
    "ros1_definition",
]

logger = logging.getLogger("belvedere.bags")


class BagError(BelvedereError):
    """A bag that cannot be read or written as asked."""


@dataclass(frozen=True, slots=True)
class Connection:
    """One topic as one publisher offered it."""

    id: int
    topic: str
    msgtype: str
    """The store's spelling: ``geometry_msgs/msg/Twist``."""
    encoding: str
    """``ros1`` or ``cdr``."""
    md5sum: str
    """ROS 1's MD5 sum of the type ('' where the file does not say)."""
    definition: str
    """The type's definition as the file holds it (ROS 1's full text, or a ros2msg schema)."""
    callerid: str | None = None
    latching: bool = False


class BagMessage(NamedTuple):
    connection: Connection
    stamp_ns: int
    """When it was recorded (ROS 1 bags' time, MCAP's log time)."""
    data: bytes


@cache
def ros1_definition(msgtype: str) -> tuple[str, str, str]:
    """(ROS 1 name, MD5 sum, full definition text) of a store type, as genpy has them."""
    from belvedere.ros1 import message_class

    cls = message_class(msgtype)
    return cls._type, cls._md5sum, cls._full_text


@cache
def cdr_schema(msgtype: str) -> str:
    """The ros2msg schema of a store type (its definition and those it uses)."""
    text, _ = types().store.generate_msgdef(msgtype, ros_version=2)
    return text


class Decoder:
    """Turns a bag's messages into the store's objects; types the store lacks are learnt
    from the bag's definitions. A connection whose type differs from belvedere's (another
    MD5 sum) cannot be decoded: it is skipped, with one warning."""

    def __init__(self) -> None:
        self._usable: dict[tuple[str, str, str], bool] = {}

    def usable(self, conn: Connection) -> bool:
        key = (conn.msgtype, conn.md5sum, conn.encoding)
        known = self._usable.get(key)
        if known is None:
            known = self._usable[key] = self._check(conn)
        return known

    def _check(self, conn: Connection) -> bool:
        store = types().store
        if conn.msgtype not in store.fielddefs and not self._learn(conn):
            return False
        if conn.encoding == "ros1" and conn.md5sum and conn.md5sum != "*":
            ours = ros1_definition(conn.msgtype)[1]
            if ours != conn.md5sum:
                logger.warning(
                    "skipping %s: its %s (MD5 %s) is not belvedere's (MD5 %s)",
                    conn.topic,
                    short(conn.msgtype),
                    conn.md5sum,
                    ours,
                )
                return False
        return True

    @staticmethod
    def _learn(conn: Connection) -> bool:
        try:
            found = get_types_from_msg(conn.definition, conn.msgtype)
            store = types().store
            found = {k: v for k, v in found.items() if k not in store.fielddefs}
            store.register(found)
            types().resolve(conn.msgtype)
        except (TypesysError, MessageTypeError, ValueError, KeyError) as err:
            logger.warning(
                "skipping %s: cannot read its type %s: %s", conn.topic, conn.msgtype, err
            )
            return False
        return True

    @staticmethod
    def decode(message: BagMessage) -> Any:
        conn = message.connection
        store = types().store
        if conn.encoding == "ros1":
            return store.deserialize_ros1(message.data, conn.msgtype)
        return store.deserialize_cdr(message.data, conn.msgtype)


def encode(msg: Any, encoding: str) -> bytes:
    """A store object in ``encoding`` (``ros1`` or ``cdr``)."""
    if encoding == "ros1":
        return bytes(types().store.serialize_ros1(msg, msg.__msgtype__))
    return types().serialize(msg)


def transcode(data: bytes, msgtype: str, source: str, target: str) -> bytes:
    """Bytes of one encoding in another (through the store's object)."""
    if source == target:
        return data
    store = types().store
    obj = (
        store.deserialize_ros1(data, msgtype)
        if source == "ros1"
        else store.deserialize_cdr(data, msgtype)
    )
    return encode(obj, target)
