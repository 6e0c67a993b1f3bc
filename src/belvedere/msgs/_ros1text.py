"""What ROS 1 says about a type in the store: its definition text, genmsg's MD5 sum and the
full text (the definition, then each type it uses after a ``MSG: pkg/Type`` line), as bags,
Foxglove's ``ros1msg`` schemas and the graph's type queries carry them.

Here, below ``ros1``, because the graph answers other processes' questions about a type with
this text (a process without the user's package learns it so), and genpy's classes in ``ros1``
take the same values from here.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import cache
from typing import Any, Final

from rosbags.interfaces import Nodetype

from belvedere.msgs._genmsg import PLACEHOLDER
from belvedere.msgs._types import types

__all__ = ["SEPARATOR", "Ros1Text", "ros1_name", "ros1_text"]

TIME: Final = "builtin_interfaces/msg/Time"
DURATION: Final = "builtin_interfaces/msg/Duration"
SPECIAL: Final = {TIME: "time", DURATION: "duration"}
SEPARATOR: Final = "=" * 80


@dataclass(frozen=True)
class Ros1Text:
    """One message type (or one half of a service) as genmsg describes it."""

    name: str
    """The ROS 1 name: ``geometry_msgs/Twist``, ``std_srvs/SetBoolRequest``."""
    md5_text: str
    md5sum: str
    text: str
    """The definition: the user's file as written, else one declaration a line (the store
    keeps no comments)."""
    dependencies: tuple[str, ...]
    """Store names of the message types used, in genmsg's order (depth first, each once)."""

    @property
    def full_text(self) -> str:
        parts = [self.text]
        for dep in self.dependencies:
            parts.append(f"{SEPARATOR}\nMSG: {ros1_name(dep)}\n{ros1_text(dep).text}")
        return "\n".join(parts)


def ros1_name(name: str) -> str:
    """``pkg/msg/Type`` → ``pkg/Type``; ``pkg/srv/Name_Request`` → ``pkg/NameRequest``."""
    if name in SPECIAL:
        return SPECIAL[name]
    pkg, kind, base = name.split("/")
    if kind == "srv":
        base = base.replace("_Request", "Request").replace("_Response", "Response")
    return f"{pkg}/{base}"


def _constant_text(typ: str, value: Any) -> str:
    if typ == "bool":
        return str(int(value))
    return str(value)


def field_shape(desc: Any) -> tuple[Any, Any, int | None]:
    """(node type, detail, array) of a store field: array None for one value, 0 for a
    variable-length array, else the fixed length."""
    node: Any = desc[0]
    detail: Any = desc[1]
    array: int | None = None
    if node in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        (node, detail), length = detail
        array = int(length) if desc[0] == Nodetype.ARRAY else 0
    return node, detail, array


def slot_type(base: str, array: int | None) -> str:
    """A field's type as genpy spells it (``float64[9]``, ``std_msgs/Header``), ``base`` a
    primitive, ``time``/``duration`` or a message's store name."""
    ros1 = base if base in SPECIAL.values() or "/" not in base else ros1_name(base)
    return ros1 if array is None else f"{ros1}[{array or ''}]"


@cache
def ros1_text(name: str) -> Ros1Text:
    """The ROS 1 description of a store type (by its store name, which must be known)."""
    registry = types()
    constants, fielddefs = registry.store.fielddefs[name]
    if [f[0] for f in fielddefs] == [PLACEHOLDER]:
        fielddefs = []  # how the store keeps a message with no fields
    own = registry.definitions.get(name)  # a type of the user's: its text and values as written
    if own is not None:
        md5_lines = [f"{c.type} {c.name}={c.text}" for c in own.constants]
    else:
        md5_lines = [f"{t} {c}={_constant_text(t, value)}" for c, t, value in constants]
    text_lines = list(md5_lines)
    direct: list[str] = []
    for fname, desc in fielddefs:
        node, detail, array = field_shape(desc)
        if node == Nodetype.NAME and str(detail) not in SPECIAL:
            base = str(detail)
            md5_lines.append(f"{ros1_text(base).md5sum} {fname}")
            if base not in direct:
                direct.append(base)
        else:
            base = SPECIAL[str(detail)] if node == Nodetype.NAME else str(detail[0])
            md5_lines.append(f"{slot_type(base, array)} {fname}")
        text_lines.append(f"{slot_type(base, array)} {fname}")
    md5_text = "\n".join(md5_lines)
    deps: list[str] = []
    for dep in direct:
        for item in (dep, *ros1_text(dep).dependencies):
            if item not in deps:
                deps.append(item)
    return Ros1Text(
        name=ros1_name(name),
        md5_text=md5_text,
        md5sum=hashlib.md5(md5_text.encode()).hexdigest(),
        text=own.text if own is not None else "\n".join(text_lines) + "\n",
        dependencies=tuple(deps),
    )
