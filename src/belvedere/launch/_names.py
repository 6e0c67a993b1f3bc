"""roslaunch's name arithmetic (rosgraph.names): joins that leave ``/global`` and ``~private``
names alone, canonical forms without doubled or trailing slashes, and the legality test that
roslaunch only warns about."""

from __future__ import annotations

import re
from typing import Final

__all__ = ["canonical", "child_namespace", "global_ns", "is_legal", "ns_join"]

_LEGAL: Final = re.compile(r"^[~/A-Za-z][\w/]*$")


def canonical(name: str) -> str:
    """``//a//b/`` → ``/a/b``; relative names stay relative; ``''`` and ``/`` are kept."""
    if not name or name == "/":
        return name
    parts = "/".join(p for p in name.split("/") if p)
    return "/" + parts if name.startswith("/") else parts


def ns_join(ns: str, name: str) -> str:
    """Join ``name`` to ``ns`` unless it is global (``/x``) or private (``~x``)."""
    if name.startswith(("/", "~")):
        return name
    if ns == "~":
        return "~" + name
    if not ns:
        return name
    return ns + name if ns.endswith("/") else f"{ns}/{name}"


def global_ns(name: str) -> str:
    """``a`` → ``/a/`` (roslaunch keeps its namespaces with both slashes)."""
    if not name.startswith("/"):
        name = "/" + name
    return name if name.endswith("/") else name + "/"


def child_namespace(ns: str, sub: str | None) -> str:
    """The namespace of a ``<group ns>``, ``<include ns>`` or ``<node ns>`` inside ``ns``
    (both with a trailing slash): a leading ``/`` makes it global."""
    if not sub:
        return ns
    return global_ns(sub if sub.startswith("/") else ns_join(ns, sub))


def is_legal(name: str) -> bool:
    """A name ROS tools accept (letters, digits, ``_``, ``/``; starting with a letter, ``/``
    or ``~``); an empty name is legal."""
    return not name or (bool(_LEGAL.match(name)) and "//" not in name)
