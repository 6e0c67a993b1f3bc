"""rosmsg and rossrv: the message and service types the type store knows, as those tools print
them (``show`` with nested types indented two spaces, ``-r`` the definition itself, ``md5``,
``list``, ``package``, ``packages``).

Whatever the store holds is listed, the standard types and any registered since (a
workspace's own message packages). The store keeps the declarations, not the file: ``-r``
prints them without the ``.msg`` file's comments, constants before fields, and every type in
full (``std_msgs/Header header`` where the file says ``Header header``).
"""

from __future__ import annotations

import difflib
from typing import Final, Literal

from belvedere.msgs import MessageTypeError, canonical, types
from belvedere.ros1._spec import MessageSpec, message_spec, ros1_name, service_md5

__all__ = [
    "Kind",
    "md5_text",
    "package_types",
    "packages",
    "show_text",
    "type_names",
]

Kind = Literal["msg", "srv"]

_PRIMITIVES: Final = frozenset({"builtin_interfaces/msg/Time", "builtin_interfaces/msg/Duration"})
"""ROS 1's ``time`` and ``duration``, which the store keeps as messages."""


def type_names(kind: Kind) -> list[str]:
    """Every type of ``kind`` the store knows, as ``pkg/Type``, in rosmsg list's order."""
    registry = types()
    if kind == "srv":
        return sorted(ros1_name(name) for name in registry.service_names())
    return sorted(ros1_name(n) for n in registry.message_names() if n not in _PRIMITIVES)


def packages(kind: Kind) -> list[str]:
    """The packages that hold types of ``kind`` (rosmsg packages)."""
    return sorted({name.partition("/")[0] for name in type_names(kind)})


def package_types(kind: Kind, package: str) -> list[str]:
    """The types of ``kind`` in ``package`` (rosmsg package); an unknown package is an error
    naming close ones."""
    found = [name for name in type_names(kind) if name.partition("/")[0] == package]
    if not found:
        msg = f"no {_WORD[kind]} types in package {package!r}"
        raise MessageTypeError(msg, hint=_did_you_mean(package, packages(kind)))
    return found


def _lookup(kind: Kind, name: str) -> list[str]:
    """The ``pkg/Type`` names ``name`` means: itself, or with no package, every package's
    type of that name (as rosmsg searches them all). Unknown: an error with close names."""
    known = type_names(kind)
    if "/" in name:
        full = "/".join(p for p in canonical(name, kind).split("/") if p not in ("msg", "srv"))
        if full in known:
            return [full]
    else:
        matches = [k for k in known if k.partition("/")[2] == name]
        if matches:
            return matches
    msg = f"unknown {_WORD[kind]} type {name!r}"
    candidates = known if "/" in name else sorted({k.partition("/")[2] for k in known})
    raise MessageTypeError(msg, hint=_did_you_mean(name, candidates))


_WORD: Final = {"msg": "message", "srv": "service"}


def _did_you_mean(name: str, candidates: list[str]) -> str:
    # A type's own name in another package first (geometry_msgs/Header: std_msgs/Header)
    tail = name.rpartition("/")[2].lower()
    close = [c for c in candidates if "/" in name and c.rpartition("/")[2].lower() == tail][:3]
    close = close or difflib.get_close_matches(name, candidates, n=3, cutoff=0.6)
    if close:
        return "did you mean " + ", ".join(close) + "?"
    return "see 'belvedere msg list' and 'belvedere srv list'"


def _spec_lines(spec: MessageSpec, indent: str, raw: bool) -> list[str]:
    """A message's declarations: constants first (as the definition text has them), each
    field, and under a field of a message type that type's, two spaces further in."""
    if raw:
        return spec.text.splitlines() if spec.fields or spec.constants else []
    lines = [indent + line for line in spec.text.splitlines()[: len(spec.constants)]]
    for field in spec.fields:
        lines.append(f"{indent}{field.slot_type} {field.ros_name}")
        if field.is_message:
            lines += _spec_lines(message_spec(field.base), indent + "  ", raw)
    return lines


def _body(kind: Kind, name: str, raw: bool) -> str:
    pkg, _, base = name.partition("/")
    if kind == "msg":
        lines = _spec_lines(message_spec(name), "", raw)
    else:
        request = message_spec(f"{pkg}/srv/{base}_Request")
        response = message_spec(f"{pkg}/srv/{base}_Response")
        lines = [*_spec_lines(request, "", raw), "---", *_spec_lines(response, "", raw)]
    return "".join(line + "\n" for line in lines)


def show_text(kind: Kind, name: str, *, raw: bool = False) -> str:
    """What ``rosmsg show NAME`` (``rossrv show``) prints, to the last blank line. A name
    without a package shows every package's type of that name, each under ``[pkg/Type]:``."""
    found = _lookup(kind, name)
    if "/" in name:
        return _body(kind, found[0], raw) + "\n"
    return "".join(f"[{full}]:\n{_body(kind, full, raw)}\n" for full in found)


def md5_text(kind: Kind, name: str) -> str:
    """What ``rosmsg md5 NAME`` (``rossrv md5``) prints."""
    found = _lookup(kind, name)

    def md5(full: str) -> str:
        pkg, _, base = full.partition("/")
        if kind == "srv":
            return service_md5(f"{pkg}/srv/{base}")
        return message_spec(full).md5sum

    if "/" in name:
        return md5(found[0]) + "\n"
    return "".join(f"[{full}]: {md5(full)}\n" for full in found)
