"""The xacro error type."""

from __future__ import annotations

from belvedere.errors import ParseError

__all__ = ["XacroError"]


class XacroError(ParseError):
    """Anything wrong in a xacro document: printed with file:line:col and the macro trail."""
