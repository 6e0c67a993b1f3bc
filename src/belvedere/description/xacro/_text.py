"""Attribute and text content as parts: literal text, compiled ``${}``, and ``$()``."""

from __future__ import annotations

from typing import Any

from belvedere.description.xacro._expr import EXPR, TEXT, tokenize
from belvedere.description.xacro._interpreter import Compiled, ExpressionError, compile_expr

__all__ = ["Part", "program", "programs", "python2_str"]

Part = str | Compiled | tuple[int, str]
"""A piece of attribute or text content: literal text, a compiled ``${}``, or a token left
to evaluate each time (a ``$()``, or a ``${}`` holding one)."""

programs: dict[str, tuple[Part, ...]] = {}
"""Every text split so far (the same strings recur in every macro call)."""


def program(text: str) -> tuple[Part, ...]:
    """``text`` split into parts, its expressions compiled (cached: macro bodies repeat)."""
    parts: list[Part] = []
    for kind, payload in tokenize(text):
        if kind == TEXT:
            parts.append(payload)
        elif kind == EXPR and "$" not in payload:
            try:
                parts.append(compile_expr(payload))
            except ExpressionError:  # reported when (and if) it is evaluated, in order
                parts.append((kind, payload))
        else:
            parts.append((kind, payload))
    result = tuple(parts)
    if len(programs) < 200_000:
        programs[text] = result
    return result


def python2_str(value: Any) -> str:
    """``str()`` as Python 2 printed a float: 12 significant digits (``0.3``, not
    ``0.30000000000000004``); everything else as Python 3 prints it."""
    if type(value) is not float:
        return str(value)
    text = f"{value:.12g}"
    if text.lstrip("-").isdigit():
        text += ".0"
    return text
