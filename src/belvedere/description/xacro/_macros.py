"""Macro definitions and the tables that scope them."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Final

from belvedere.xmldom import Element

__all__ = ["Macro", "MacroTable", "parse_macro_params"]


@dataclass
class Macro:
    name: str
    body: Element
    params: list[str] = field(default_factory=list)
    defaults: dict[str, tuple[str | None, str | None]] = field(default_factory=dict)
    """param → (name to forward from the caller's scope, default text)."""


class MacroTable:
    """Macros visible at one level; lookups fall back to the parent level."""

    __slots__ = ("macros", "parent")

    def __init__(self, parent: MacroTable | None = None) -> None:
        self.parent = parent
        self.macros: dict[str, Macro | MacroTable] = {}

    def get(self, name: str) -> Macro | MacroTable | None:
        t: MacroTable | None = self
        while t is not None:
            m = t.macros.get(name)
            if m is not None:
                return m
            t = t.parent
        return None

    def top(self) -> MacroTable:
        t = self
        while t.parent is not None:
            t = t.parent
        return t


_MACRO_PARAM: Final = re.compile(
    r"^\s*([^\s:=]+?)\s*:?=\s*(\^\|?)?(\$\{.*?\}|\$\(.*?\)|(?:'.*?'|\".*?\"|[^\s'\"]+)+|)(?:\s+|$)(.*)"
)


def parse_macro_params(spec: str) -> tuple[list[str], dict[str, tuple[str | None, str | None]]]:
    """Split a ``params`` attribute: ``a b:=1 c:=^ d:=^|2 *blk **blks``."""
    params: list[str] = []
    defaults: dict[str, tuple[str | None, str | None]] = {}
    rest = spec
    while rest:
        m = _MACRO_PARAM.match(rest)
        if m:
            param, forward, default, rest = m.groups()
            defaults[param] = (param if forward else None, default or None)
        else:
            parts = rest.lstrip().split(None, 1)
            if not parts:
                break
            param = parts[0]
            rest = parts[1] if len(parts) > 1 else ""
        params.append(param)
    return params, defaults
