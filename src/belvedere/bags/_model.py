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

from rosbags.interfaces import Nodetype
from rosbags.typesys import Stores, TypesysError, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

from belvedere.bounded import DEFINITION_BYTES, describe_size
from belvedere.errors import BelvedereError
from belvedere.msgs import (
    DefinitionError,
    InterfaceError,
    MessageTypeError,
    message_from_data,
    read_full_text,
    short,
    types,
)
from belvedere.msgs._genmsg import typedef

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
    """``ros1`` or ``cdr`` (or another an MCAP file names, which is not read)."""
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
    """Turns a bag's messages into the store's objects.

    A type the store lacks is learnt from the bag's definition. A type the store has, but
    laid out otherwise in the bag (a ROS 2 ``std_msgs/Header`` without ``seq``, a message of
    another ROS version: another MD5 sum), is read with the bag's own definition and copied
    field by field, by name (case aside), into belvedere's type; fields the bag lacks keep
    their defaults. A connection whose definition cannot be read is skipped, with a warning.
    """

    def __init__(self) -> None:
        self._plans: dict[tuple[str, str, str, str], Typestore | bool | None] = {}
        self._parse_budget = DEFINITION_BYTES
        """What the definitions it parses may still add up to (bytes)."""

    def usable(self, conn: Connection, where: str = "") -> bool:
        """Whether ``conn``'s messages can be decoded; the first time a connection's type is
        asked about and they cannot, a warning says why (beginning ``where: ``, the bag's
        name, if given)."""
        return self._plan(conn, where) is not False

    def _plan(self, conn: Connection, where: str = "") -> Typestore | bool | None:
        """None: the store reads it; a type store: the bag's own layout; False: unreadable."""
        key = (conn.msgtype, conn.encoding, conn.md5sum, conn.definition)
        if key not in self._plans:
            self._plans[key] = self._check(conn, f"{where}: " if where else "")
        return self._plans[key]

    def _check(self, conn: Connection, where: str) -> Typestore | bool | None:
        if conn.encoding not in ("ros1", "cdr"):
            logger.warning(
                "%sskipping %s: its messages are encoded as %r, which belvedere does not read",
                where,
                conn.topic,
                conn.encoding,
            )
            return False
        store = types().store
        known = conn.msgtype in store.fielddefs
        has_md5 = conn.encoding == "ros1" and conn.md5sum not in ("", "*")
        if known and has_md5 and ros1_definition(conn.msgtype)[1] == conn.md5sum:
            return None
        size = len(conn.definition)
        if size > self._parse_budget:
            logger.warning(
                "%sskipping %s: its type's definition (%s) would take the definitions read "
                "past the %s belvedere parses per run",
                where,
                conn.topic,
                describe_size(size),
                describe_size(DEFINITION_BYTES),
            )
            return False
        self._parse_budget -= size
        if conn.encoding == "ros1" and conn.definition:
            return self._full_text(conn, where, known)
        try:
            found = get_types_from_msg(conn.definition, conn.msgtype) if conn.definition else {}
            _check_acyclic(found, store.fielddefs)
        except (TypesysError, ValueError, KeyError) as err:
            if known and conn.encoding == "cdr":
                return None  # no definition to go by: the store's
            return self._unreadable(conn, where, err)
        if not found:
            return None if known else self._unknown(conn, where)
        differs = [
            n for n, d in found.items() if n in store.fielddefs and d[1] != store.fielddefs[n][1]
        ]
        return self._layout(conn, where, known, found, [short(n) for n in differs])

    def _full_text(self, conn: Connection, where: str, known: bool) -> Typestore | bool | None:
        """A ROS 1 definition (a bag's ``message_definition``, an MCAP ``ros1msg`` schema),
        read by genmsg's rules and checked against the connection's MD5 sum: a type the
        store lacks is learnt from it; one it lays out otherwise is read in the bag's
        layout and converted."""
        source = f"{where}connection {conn.id} ({conn.topic})"
        try:
            full = read_full_text(conn.definition, conn.msgtype, source)
        except (InterfaceError, DefinitionError) as err:
            return self._unreadable(conn, where, err)
        given = conn.md5sum
        if given not in ("", "*") and given != full.md5sum:
            logger.warning(
                "%sskipping %s (connection %d): its definition of %s does not match the "
                "connection's MD5 sum (%s given, %s computed from the definition)",
                where,
                conn.topic,
                conn.id,
                short(conn.msgtype),
                given,
                full.md5sum,
            )
            return False
        mismatches = full.mismatches()
        if not mismatches:
            types().adopt(full.new_types())
            return None
        found = {name: typedef(d) for name, d in full.definitions.items()}
        return self._layout(conn, where, known, found, [m.describe() for m in mismatches])

    def _layout(
        self, conn: Connection, where: str, known: bool, found: dict[str, Any], differs: list[str]
    ) -> Typestore | bool | None:
        """Types of the bag (``found``: the store's field definitions), some of them
        (``differs``) other than the store's, or none."""
        store = types().store
        try:
            if not differs:
                store.register({n: d for n, d in found.items() if n not in store.fielddefs})
                types().resolve(conn.msgtype)
                return None
            own = get_typestore(Stores.EMPTY)
            own.register(found)
            if not known:  # belvedere's version: the bag's fields, with the store's parts
                store.register({n: d for n, d in found.items() if n not in store.fielddefs})
        except (TypesysError, MessageTypeError, ValueError, KeyError) as err:
            return self._unreadable(conn, where, err)
        logger.warning(
            "%s%s: the bag's %s differs from belvedere's (%s): converting it field by field",
            where,
            conn.topic,
            short(conn.msgtype),
            ", ".join(differs),
        )
        return own

    @staticmethod
    def _unreadable(conn: Connection, where: str, err: Exception) -> bool:
        logger.warning(
            "%sskipping %s (connection %d): cannot read its type %s: %s",
            where,
            conn.topic,
            conn.id,
            conn.msgtype,
            _why(err),
        )
        return False

    @staticmethod
    def _unknown(conn: Connection, where: str) -> bool:
        logger.warning(
            "%sskipping %s: its type %s is unknown here", where, conn.topic, conn.msgtype
        )
        return False

    def decode(self, message: BagMessage) -> Any:
        conn = message.connection
        plan = self._plan(conn)
        store = types().store if plan is None or plan is False else plan
        assert isinstance(store, Typestore)
        if conn.encoding == "ros1":
            obj = store.deserialize_ros1(message.data, conn.msgtype)
        else:
            obj = store.deserialize_cdr(message.data, conn.msgtype)
        return obj if plan is None else _convert(obj, conn.msgtype)


def _check_acyclic(found: dict[str, Any], known: dict[str, Any]) -> None:
    """Raise ValueError if a type of ``found`` holds itself (no ROS message can: its size,
    and its MD5 sum, would be infinite; a definition saying so would recurse without end)."""
    fields = {**known, **found}
    done: set[str] = set()

    def parts(name: str) -> list[str]:
        out = []
        for _, (kind, detail) in fields.get(name, ((), ()))[1]:
            if kind == Nodetype.NAME:
                out.append(str(detail))
            elif kind in (Nodetype.ARRAY, Nodetype.SEQUENCE) and detail[0][0] == Nodetype.NAME:
                out.append(str(detail[0][1]))
        return out

    for start in found:
        path = [start]
        todo = [iter(parts(start))]
        while todo:  # depth first, without recursion (a hostile chain may be long)
            step = next(todo[-1], None)
            if step is None:
                done.add(path.pop())
                todo.pop()
            elif step in path:
                msg = f"{step} holds itself"
                raise ValueError(msg)
            elif step not in done:
                path.append(step)
                todo.append(iter(parts(step)))


def _why(err: BaseException) -> str:
    """One short line saying why a definition cannot be read (a parser's message may hold
    the whole definition, which is the bag's text, over many lines)."""
    if str(err).strip().startswith("Could not parse"):
        return "its definition does not parse"
    if isinstance(err, InterfaceError):  # genmsg's rules: the line of the definition
        line = f"line {err.location.line}: " if err.location and err.location.line else ""
        return f"its definition does not parse ({line}{_short(err.message)})"
    if isinstance(err, DefinitionError):  # the source is the warning's own start
        return _short(err.reason)
    return one_line(err)


def _short(text: str) -> str:
    line = text.strip().splitlines()[0] if text.strip() else ""
    return line if len(line) <= 160 else line[:157] + "..."


def one_line(err: BaseException) -> str:
    """An error's message as one short line (a library's may hold the bag's own bytes, over
    many lines)."""
    lines = str(err).strip().splitlines()
    line = lines[0] if lines else type(err).__name__
    return line if len(line) <= 120 else line[:117] + "..."


def _convert(obj: Any, msgtype: str) -> Any:
    """A message of another layout as the store's ``msgtype``: fields by name (case aside)."""
    store = types().store
    cls = store.types[msgtype]
    source = {name.lower(): name for name in getattr(obj, "__dataclass_fields__", {})}
    default: Any = None
    values = {}
    for name, (kind, detail) in store.fielddefs[msgtype][1]:
        theirs = source.get(name.lower())
        if theirs is None:
            if default is None:
                default = message_from_data(msgtype, None)
            values[name] = getattr(default, name)
            continue
        value = getattr(obj, theirs)
        if kind == Nodetype.NAME:
            value = _convert(value, str(detail))
        elif kind in (Nodetype.ARRAY, Nodetype.SEQUENCE) and detail[0][0] == Nodetype.NAME:
            value = [_convert(v, str(detail[0][1])) for v in value]
        values[name] = value
    return cls(**values)


def encode(msg: Any, encoding: str) -> bytes:
    """A store object in ``encoding`` (``ros1`` or ``cdr``)."""
    if encoding == "ros1":  # a large last string or byte array copied once, not thrice
        return b"".join(types().ros1_parts(msg, msg.__msgtype__))
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
