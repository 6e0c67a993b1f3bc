"""What genpy knows about a message type, derived from the type store's field definitions:
ROS 1 names and field type strings, the MD5 sum (as ``genmsg`` computes it), and the full
definition text.

The store keeps ROS 1 messages as ``pkg/msg/Type`` and service halves as
``pkg/srv/Name_Request``; genpy calls them ``pkg/Type`` and ``pkg/NameRequest``. ROS 1's
``time`` and ``duration`` are ``builtin_interfaces/msg/Time`` and ``…/Duration`` there.
"""

from __future__ import annotations

import hashlib
import keyword
from dataclasses import dataclass
from functools import cache
from typing import Any

from rosbags.interfaces import Nodetype

from belvedere.msgs import PLACEHOLDER, types
from belvedere.msgs._ros1text import (
    DURATION,
    SEPARATOR,
    SPECIAL,
    TIME,
    field_shape,
    ros1_name,
    ros1_text,
)

__all__ = [
    "DURATION",
    "TIME",
    "FieldSpec",
    "MessageSpec",
    "message_spec",
    "ros1_name",
    "service_md5",
    "store_name",
]


@dataclass(frozen=True)
class FieldSpec:
    """One field of a message type."""

    name: str
    """The attribute's name (a Python keyword gets a trailing ``_``, as genpy does)."""
    ros_name: str
    """The field's name in the definition."""
    base: str
    """A primitive (``float64``, ``string``, ``time``…) or a message's store name."""
    is_message: bool
    array: int | None
    """None for a single value, 0 for a variable-length array, else the fixed length."""

    @property
    def base_ros1(self) -> str:
        return ros1_name(self.base) if self.is_message else self.base

    @property
    def slot_type(self) -> str:
        """The type as genpy's ``_slot_types`` spells it (``float64[9]``, ``std_msgs/Header``)."""
        if self.array is None:
            return self.base_ros1
        return f"{self.base_ros1}[{self.array or ''}]"


@dataclass(frozen=True)
class MessageSpec:
    """One message type (or one half of a service)."""

    store_name: str
    name: str
    """The ROS 1 name: ``geometry_msgs/Twist``, ``std_srvs/SetBoolRequest``."""
    constants: tuple[tuple[str, str, Any], ...]
    """(name, type, value) in definition order."""
    fields: tuple[FieldSpec, ...]
    md5_text: str
    md5sum: str
    text: str
    """The definition, one declaration a line (the store keeps no comments)."""
    dependencies: tuple[str, ...]
    """Store names of the message types used, in genmsg's order (depth first, each once)."""

    @property
    def full_text(self) -> str:
        parts = [self.text]
        for dep in self.dependencies:
            parts.append(f"{SEPARATOR}\nMSG: {ros1_name(dep)}\n{message_spec(dep).text}")
        return "\n".join(parts)

    @property
    def has_header(self) -> bool:
        first = self.fields[0] if self.fields else None
        return (
            first is not None
            and first.is_message
            and first.array is None
            and first.base == "std_msgs/msg/Header"
        )


def store_name(name: str) -> str:
    """The store's name for a ROS 1 message name (``pkg/Type``, ``pkg/NameRequest``, or
    already a store name); an unknown name is a :class:`MessageTypeError`."""
    fielddefs = types().store.fielddefs
    if name in fielddefs:
        return name
    pkg, _, base = name.partition("/")
    types().learn(pkg)  # a package of the user's, read when first named
    if "/" not in base:
        for suffix in ("Request", "Response"):
            candidate = f"{pkg}/srv/{base.removesuffix(suffix)}_{suffix}"
            if base.endswith(suffix) and candidate in fielddefs:
                return candidate
    return types().resolve(name)


@cache
def message_spec(name: str) -> MessageSpec:
    """The spec of a message type, by its store name."""
    full = store_name(name)
    constants, fielddefs = types().store.fielddefs[full]
    if [f[0] for f in fielddefs] == [PLACEHOLDER]:
        fielddefs = []  # how the store keeps a message with no fields
    fields: list[FieldSpec] = []
    for fname, desc in fielddefs:
        node, detail, array = field_shape(desc)
        if node == Nodetype.NAME:
            base = str(detail)
            is_message = base not in SPECIAL
            if not is_message:
                base = SPECIAL[base]
        else:
            base = str(detail[0])
            is_message = False
        fields.append(
            FieldSpec(
                name=f"{fname}_" if keyword.iskeyword(fname) or fname == "self" else fname,
                ros_name=fname,
                base=base,
                is_message=is_message,
                array=array,
            )
        )
    described = ros1_text(full)
    return MessageSpec(
        store_name=full,
        name=described.name,
        constants=tuple((c, t, v) for c, t, v in constants),
        fields=tuple(fields),
        md5_text=described.md5_text,
        md5sum=described.md5sum,
        text=described.text,
        dependencies=described.dependencies,
    )


@cache
def service_md5(service: str) -> str:
    """The MD5 sum of a service (``pkg/srv/Name``): over both halves' MD5 texts."""
    request = message_spec(f"{service}_Request")
    response = message_spec(f"{service}_Response")
    digest = hashlib.md5(request.md5_text.encode())
    digest.update(response.md5_text.encode())
    return digest.hexdigest()
