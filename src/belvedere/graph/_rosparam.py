"""How Debian's ``rosparam`` (ros_comm 1.15) writes parameters, so that ``belvedere param``
prints what it prints: ``get`` as ``yaml.dump`` (with its quirks kept: a trailing blank line
after anything but a plain scalar), ``get -p``, ``dump``, the ``name=value`` lines of ``-v``,
and the ``_ns`` key of the documents ``load`` reads.

Binary values (``set -b``) are ``bytes`` on belvedere's graph; they are written as rosparam
meant to write its ``xmlrpclib.Binary`` (``!!binary`` with one base64 line), which Debian's
rosparam itself cannot do under Python 3 (it fails with a traceback).
"""

from __future__ import annotations

import base64
from typing import Any

import yaml

from belvedere.yamlfile import load_yaml_documents

__all__ = ["documents", "dump_text", "get_text", "leaf_lines", "ns_join", "shown"]


_END = "\n...\n"
"""The document end PyYAML writes after a plain scalar."""


class _Dumper(yaml.SafeDumper):
    """``yaml.dump``'s output for the values a parameter server holds."""


def _binary(dumper: yaml.SafeDumper, data: bytes) -> yaml.Node:
    text = base64.b64encode(data).decode("ascii")  # rosparam's: one line, not encodebytes'
    return dumper.represent_scalar("tag:yaml.org,2002:binary", text, style="|")


_Dumper.add_representer(bytes, _binary)


def _dump(value: Any) -> str:
    return yaml.dump(value, Dumper=_Dumper)


def ns_join(ns: str, name: str) -> str:
    """rosgraph's ``ns_join``: a global name stays itself."""
    if name.startswith("/") or not ns:
        return name
    return ns + name if ns.endswith("/") else f"{ns}/{name}"


def shown(value: Any) -> str:
    """A value as rosparam's ``%s`` shows it (Python's ``str``; binary as ``Binary`` does)."""
    if isinstance(value, bytes):
        return value.decode("latin-1")
    return str(value)


def get_text(value: Any, *, pretty: bool = False) -> str:
    """``rosparam get [-p]``'s output."""
    if pretty and isinstance(value, dict):
        return "".join(_pretty(value, ""))
    if pretty and isinstance(value, str):
        return value + "\n"
    text = _dump(value)
    # rosparam strips the document end PyYAML writes after a plain scalar (its #1617), then
    # adds a newline (#3761): a collection or a quoted scalar ends with a blank line
    return text.removesuffix(_END) + "\n"


def _pretty(value: dict[str, Any], indent: str) -> list[str]:
    """rosparam's ``_pretty_print`` (its help says "not YAML-safe": a list inside is written
    without its indentation, as rosparam writes it)."""
    out: list[str] = []
    for key in sorted(value):
        item = value[key]
        if isinstance(item, dict):
            out += [f"{indent}{key}:\n", *_pretty(item, indent + "  ")]
        elif isinstance(item, str) and "\n" in item:
            out += [f"{indent}{key}: |\n", *(f"{indent}  {line}\n" for line in item.split("\n"))]
        elif isinstance(item, str):
            out.append(f"{indent}{key}: {item}\n")
        else:
            text = _dump(item)  # its document end cut, not the newline before it
            out.append(f"{indent}{key}: {text[:-4] if text.endswith(_END) else text}")
    return out


def dump_text(value: Any) -> str:
    """``rosparam dump``'s YAML."""
    return _dump(value)


def leaf_lines(value: Any, ns: str) -> list[str]:
    """rosparam's ``print_params`` (the ``-v`` lines of ``load`` and ``dump``): ``name=value``
    for every leaf in the dictionaries' order; a value that is not one, alone."""
    if not isinstance(value, dict):
        return [shown(value)]
    out: list[str] = []
    for key, item in value.items():
        if isinstance(item, dict):
            out += leaf_lines(item, ns_join(ns, key))
        else:
            out.append(f"{ns_join(ns, key)}={shown(item)}")
    return out


def documents(text: str, namespace: str, *, source: str) -> list[tuple[Any, str, bool]]:
    """``rosparam load``'s reading: each document of ``text`` with the namespace it goes to,
    ``namespace`` or, for a mapping with an ``_ns`` key, that key joined to it (the key
    itself is not a parameter), and whether it had one. Empty documents set nothing."""
    out: list[tuple[Any, str, bool]] = []
    for doc in load_yaml_documents(text, path=source):
        if doc is None:
            continue
        named = isinstance(doc, dict) and "_ns" in doc
        ns = ns_join(namespace, str(doc.pop("_ns"))) if named else namespace
        out.append((doc, ns, named))
    return out
