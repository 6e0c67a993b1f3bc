"""rosmsg and rossrv: the message and service types the type store knows, as those tools print
them (``show`` with nested types indented two spaces, ``-r`` the definition itself, ``md5``,
``list``, ``package``, ``packages``).

Whatever the store holds is listed, the standard types and any registered since (a
workspace's own message packages). The store keeps the declarations, not the file: ``-r``
prints them without the ``.msg`` file's comments, constants before fields, and every type in
full (``std_msgs/Header header`` where the file says ``Header header``).
"""

from __future__ import annotations

from typing import Final, Literal

from belvedere.errors import did_you_mean
from belvedere.msgs import MessageTypeError, canonical, types
from belvedere.ros1._spec import MessageSpec, message_spec, ros1_name, service_md5

__all__ = [
    "Kind",
    "known_type",
    "md5_text",
    "package_types",
    "service_args",
    "show_text",
    "type_names",
    "type_packages",
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


def type_packages(kind: Kind) -> list[str]:
    """The packages that hold types of ``kind`` (rosmsg packages)."""
    return sorted({name.partition("/")[0] for name in type_names(kind)})


def package_types(kind: Kind, package: str) -> list[str]:
    """The types of ``kind`` in ``package`` (rosmsg package); an unknown package is an error
    naming close ones."""
    found = [name for name in type_names(kind) if name.partition("/")[0] == package]
    if not found:
        msg = f"no {_WORD[kind]} types in package {package!r}"
        raise MessageTypeError(msg, hint=_did_you_mean(package, type_packages(kind)))
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


def known_type(kind: Kind, name: str) -> str:
    """``pkg/Type`` of a type the store knows (named in full), or an error with the closest."""
    found = _lookup(kind, name if "/" in name else f"/{name}")
    return found[0]


def _did_you_mean(name: str, candidates: list[str]) -> str:
    # A type's own name in another package first (geometry_msgs/Header: std_msgs/Header)
    tail = name.rpartition("/")[2].lower()
    same = [c for c in candidates if "/" in name and c.rpartition("/")[2].lower() == tail]
    if same:
        return "did you mean " + " or ".join(same[:3]) + "?"
    return did_you_mean(name, candidates, quote=False) or (
        "see 'belvedere msg list' and 'belvedere srv list'"
    )


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


def service_args(service: str) -> list[str]:
    """The fields of a service's request (rosservice args), by the service's store name
    (``std_srvs/srv/SetBool``) or ROS 1 name."""
    spec = message_spec(f"{canonical(service, 'srv')}_Request")
    return [field.ros_name for field in spec.fields]
