"""Types learnt from a definition that came with the data: a ROS 1 bag connection's
``message_definition``, an MCAP ``ros1msg`` schema, another process's answer on the graph.

That text is genmsg's full text: the type's definition, then each type it uses after a line
of ``=`` and a ``MSG: pkg/Type`` line. It is read by genmsg's rules (:mod:`._genmsg`, the
same as the user's files), its MD5 sum computed as genmsg does and checked against the one
that came with it, and each type in it compared with the one this process knows by that
name, so that bytes are never read with a layout they were not written in. The text is
untrusted input: its size and the number of its parts are bounded, and every mistake is an
error naming where the text came from.
"""

from __future__ import annotations

import hashlib
import re
from dataclasses import dataclass
from typing import Final

from belvedere.bounded import DEFINITION_BYTES, describe_size
from belvedere.errors import BelvedereError, SourceLocation
from belvedere.msgs._genmsg import (
    BUILTIN_TYPES,
    Definition,
    InterfaceError,
    parse_message,
    store_type,
)
from belvedere.msgs._ros1text import ros1_name, ros1_text
from belvedere.msgs._types import canonical, types

__all__ = [
    "MAX_PARTS",
    "DefinitionError",
    "FullText",
    "Mismatch",
    "learn_full_text",
    "learn_service_text",
    "read_full_text",
]

MAX_PARTS: Final = 256
"""Types one full text may define: real ones hold a few dozen (a PointCloud2's 5, an
OccupancyGrid's 7); the bound keeps a hostile one from nesting past Python's recursion."""
_SEPARATOR: Final = re.compile(r"^=+\s*$")
_MSG_LINE: Final = re.compile(r"^MSG:\s*(\S+)\s*$")


class DefinitionError(BelvedereError):
    """A definition that came with the data cannot be used: too big, malformed, or not the
    type its MD5 sum or this process's own type says."""

    def __init__(self, where: str, reason: str) -> None:
        super().__init__(f"{where}: {reason}")
        self.where = where
        self.reason = reason


@dataclass(frozen=True)
class Mismatch:
    """A type the text defines otherwise than this process knows it."""

    name: str
    """The store name."""
    theirs: str
    ours: str
    """The two MD5 sums."""

    def describe(self) -> str:
        return (
            f"{ros1_name(self.name)} here is not the one it was written with "
            f"(MD5 sum {self.ours} here, {self.theirs} there)"
        )


@dataclass(frozen=True)
class FullText:
    """A full text read: the types it defines (store names; the top one first) and the MD5
    sum of each, computed from the text."""

    msgtype: str
    definitions: dict[str, Definition]
    md5sums: dict[str, str]

    @property
    def md5sum(self) -> str:
        return self.md5sums[self.msgtype]

    def mismatches(self) -> list[Mismatch]:
        """The types of the text this process knows, with another MD5 sum."""
        store = types().store.fielddefs
        out = []
        for name, theirs in self.md5sums.items():
            if name in store:
                ours = ros1_text(name).md5sum
                if ours != theirs:
                    out.append(Mismatch(name, theirs, ours))
        return out

    def new_types(self) -> dict[str, Definition]:
        """The types of the text this process does not know yet."""
        store = types().store.fielddefs
        return {n: d for n, d in self.definitions.items() if n not in store}


def read_full_text(text: str, msgtype: str, where: str) -> FullText:
    """The types of a full text for ``msgtype`` (a store name); ``where`` names the text's
    source in errors (``x.bag: connection 3 (/person_info)``), with the line in the text."""
    if len(text.encode()) > DEFINITION_BYTES:
        msg = (
            f"the definition of {ros1_name(msgtype)} is {describe_size(len(text))}, "
            f"past the {describe_size(DEFINITION_BYTES)} belvedere reads of one"
        )
        raise DefinitionError(where, msg)
    definitions: dict[str, Definition] = {}
    lines: list[str] = []
    name, first = msgtype, 1
    parts = [(name, first, lines)]
    for number, line in enumerate(text.split("\n"), start=1):
        if _SEPARATOR.match(line) and len(line) >= 3:
            parts.append(("", number + 1, []))
            if len(parts) > MAX_PARTS:
                msg = f"the definition has more than {MAX_PARTS} types"
                raise DefinitionError(where, msg)
            continue
        name, first, lines = parts[-1]
        if not name and not lines:  # a part's first line names its type
            found = _MSG_LINE.match(line)
            if found is None:
                shown = line if len(line) <= 60 else line[:57] + "..."
                msg = f"expected 'MSG: pkg/Type' after a line of '=', not {shown!r}"
                raise InterfaceError(msg, SourceLocation(where, number))
            parts[-1] = (_part_name(found[1], where, number), number + 1, lines)
            continue
        lines.append(line)
    for name, first, lines in parts:
        if name in definitions:
            msg = f"{ros1_name(name)} is defined twice"
            raise InterfaceError(msg, SourceLocation(where, first - 1))
        definitions[name] = parse_message("\n".join(lines), name, where, first_line=first)
    return FullText(msgtype, definitions, _md5sums(definitions, where))


def _part_name(written: str, where: str, line: int) -> str:
    try:
        name = canonical(written)
    except BelvedereError as err:
        raise InterfaceError(err.message, SourceLocation(where, line)) from None
    if "/msg/" not in name:
        msg = f"{written!r} is not a message type (pkg/Type)"
        raise InterfaceError(msg, SourceLocation(where, line))
    return name


def _md5sums(definitions: dict[str, Definition], where: str) -> dict[str, str]:
    """genmsg's MD5 sum of each type of a text: its constants as written, its built-in
    fields' types, and the MD5 sums of the types it uses (from the text, else this
    process's own; a type in neither, or one that holds itself, is an error)."""
    sums: dict[str, str] = {}
    visiting: set[str] = set()

    def md5(name: str, used_at: SourceLocation | None) -> str:
        if name in sums:
            return sums[name]
        definition = definitions.get(name)
        if definition is None:
            if name in types().store.fielddefs:
                return ros1_text(name).md5sum
            msg = f"unknown type {ros1_name(name)!r}: the definition does not include it"
            raise InterfaceError(msg, used_at or SourceLocation(where))
        if name in visiting:
            msg = f"type {ros1_name(name)!r} contains itself"
            raise InterfaceError(msg, used_at, hint="a message cannot hold itself")
        visiting.add(name)
        lines = [f"{c.type} {c.name}={c.text}" for c in definition.constants]
        for field in definition.fields:
            if field.base in BUILTIN_TYPES:
                lines.append(f"{field.type} {field.name}")
            else:
                lines.append(f"{md5(store_type(field.base), field.at)} {field.name}")
        visiting.discard(name)
        sums[name] = hashlib.md5("\n".join(lines).encode()).hexdigest()
        return sums[name]

    for name in definitions:
        md5(name, None)
    return sums


def learn_full_text(text: str, msgtype: str, md5sum: str, where: str) -> list[str]:
    """Make ``msgtype`` known from a full text and the MD5 sum that came with it (``""`` or
    ``*``: none to check); the store names of the types that were new. Raises
    :class:`DefinitionError` (or the text's :class:`InterfaceError`) when the text is not
    the type its MD5 sum says, or names a type this process knows otherwise."""
    full = read_full_text(text, msgtype, where)
    if md5sum not in ("", "*") and md5sum != full.md5sum:
        msg = (
            f"the definition of {ros1_name(msgtype)} does not match its MD5 sum "
            f"({md5sum} given, {full.md5sum} computed from the text)"
        )
        raise DefinitionError(where, msg)
    mismatches = full.mismatches()
    if mismatches:
        raise DefinitionError(where, "; ".join(m.describe() for m in mismatches))
    new = full.new_types()
    types().adopt(new)
    return list(new)


def learn_service_text(service: str, halves: dict[str, tuple[str, str]], where: str) -> list[str]:
    """Make service ``service`` (``pkg/srv/Name``) known from its halves' full texts and MD5
    sums (``{"Request": (text, md5), "Response": (text, md5)}``), each checked as
    :func:`learn_full_text` checks a message's."""
    new: list[str] = []
    for half in ("Request", "Response"):
        if half not in halves:
            raise DefinitionError(where, f"the answer has no {half.lower()} of {service}")
        text, md5sum = halves[half]
        new += learn_full_text(text, f"{service}_{half}", md5sum, f"{where} ({half.lower()})")
    types().adopt({}, services=[service])
    return new
