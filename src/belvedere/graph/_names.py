"""ROS 1 graph names: global ``/a``, relative ``a``, private ``~a``, remapping, special args."""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, Final

import yaml

from belvedere import errors
from belvedere.errors import BelvedereError

__all__ = [
    "GraphNameError",
    "RosArgs",
    "did_you_mean",
    "join",
    "parse_ros_args",
    "resolve_name",
    "validate",
]

_SEGMENT: Final = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


class GraphNameError(BelvedereError):
    """A malformed graph name."""


def did_you_mean(name: str, known: Iterable[str]) -> str | None:
    """``did you mean /a or /b?``: the graph names of ``known`` closest to ``name`` (a
    misspelt topic, service or node), closest first; None when none is close."""
    return errors.did_you_mean(name, known, most=3, quote=False)


def validate(name: str) -> str:
    """A well-formed resolved name (``/ns/topic``), or an error saying what is wrong."""
    if not name.startswith("/"):
        msg = f"graph name {name!r} is not resolved (must start with '/')"
        raise GraphNameError(msg)
    for seg in name.split("/")[1:]:
        if name != "/" and not _SEGMENT.match(seg):
            msg = (
                f"graph name {name!r}: segment {seg!r} must start with a letter or '_' and hold "
                "only letters, digits and '_'"
            )
            raise GraphNameError(msg)
    return name


def join(namespace: str, name: str) -> str:
    ns = namespace.rstrip("/")
    return f"{ns}/{name}" if ns else f"/{name}"


def resolve_name(
    name: str,
    *,
    namespace: str = "/",
    node: str | None = None,
    remappings: Mapping[str, str] | None = None,
) -> str:
    """Resolve like ROS 1: ``/a`` stays, ``a`` joins the namespace, ``~a`` joins the node's
    own name; then remappings (keys and values resolved the same way) apply."""
    if not name:
        msg = "empty graph name"
        raise GraphNameError(msg)
    if name.startswith("/"):
        resolved = name
    elif name.startswith("~"):
        if node is None:
            msg = f"private name {name!r} needs a node"
            raise GraphNameError(msg)
        base = node if node.startswith("/") else join(namespace, node)
        resolved = join(base, name[1:].lstrip("/"))
    else:
        resolved = join(namespace, name)
    resolved = "/" + "/".join(p for p in resolved.split("/") if p)
    if remappings:
        resolved = remappings.get(resolved, resolved)
    return validate(resolved)


@dataclass
class RosArgs:
    """What ROS-style command-line arguments say."""

    remappings: dict[str, str] = field(default_factory=dict)
    """Unresolved ``from:=to`` pairs (resolve against the node's namespace)."""
    namespace: str | None = None
    name: str | None = None
    params: dict[str, Any] = field(default_factory=dict)
    """``_param:=value`` private parameters (YAML-typed)."""
    rest: list[str] = field(default_factory=list)


def parse_ros_args(argv: Iterable[str]) -> RosArgs:
    """Split ``__ns:=``, ``__name:=``, ``_param:=value`` and ``from:=to`` out of ``argv``."""
    out = RosArgs()
    for arg in argv:
        if ":=" not in arg:
            out.rest.append(arg)
            continue
        key, _, value = arg.partition(":=")
        if key == "__ns":
            out.namespace = value if value.startswith("/") else "/" + value
        elif key == "__name":
            out.name = value
        elif key.startswith("__"):
            continue  # __log, __ip, __hostname, __master: meaningless here
        elif key.startswith("_"):
            try:
                out.params[key[1:]] = yaml.safe_load(value)
            except yaml.YAMLError:
                out.params[key[1:]] = value
        else:
            out.remappings[key] = value
    return out
