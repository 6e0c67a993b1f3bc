"""Text with ``${expr}`` / ``$(cmd …)`` in it: the lexer.

It splits text exactly as xacro 2.1.1 does (``${…}`` cannot contain ``}``, ``$(…)`` cannot
contain ``)``, ``$$`` escapes). The expressions themselves run in ``_interpreter``.
"""

from __future__ import annotations

import re
from typing import Final

from belvedere.description.xacro._errors import XacroError

__all__ = ["EXPR", "EXTENSION", "TEXT", "Token", "tokenize"]

TEXT: Final = 0
EXPR: Final = 1
EXTENSION: Final = 2

Token = tuple[int, str]
"""(kind, payload): TEXT → literal text, EXPR → the inside of ``${}``, EXTENSION → of ``$()``."""

_LEXER: Final = re.compile(
    r"(?P<dollars>\$\$+[{(])|(?P<expr>\$\{[^}]*\})|(?P<ext>\$\([^)]*\))|(?P<text>[^$]+|\$[^{($]+|\$$)"
)
_token_cache: dict[str, tuple[Token, ...]] = {}


def tokenize(text: str) -> tuple[Token, ...]:
    """Split ``text`` into tokens (cached: the same strings recur in every macro call)."""
    toks = _token_cache.get(text)
    if toks is not None:
        return toks
    out: list[Token] = []
    pos = 0
    n = len(text)
    match = _LEXER.match
    while pos < n:
        m = match(text, pos)
        if m is None:
            msg = f"invalid expression: {text[pos:]}"
            raise XacroError(msg, hint="'${' needs a closing '}' and '$(' a closing ')'")
        kind = m.lastgroup
        tok = m.group()
        if kind == "expr":
            out.append((EXPR, tok[2:-1]))
        elif kind == "ext":
            out.append((EXTENSION, tok[2:-1]))
        elif kind == "dollars":
            out.append((TEXT, tok[1:]))
        else:
            out.append((TEXT, tok))
        pos = m.end()
    result = tuple(out)
    if len(_token_cache) < 200_000:
        _token_cache[text] = result
    return result
