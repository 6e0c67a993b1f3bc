"""Where a piece of text sits in a user's file: the column an error inside an attribute
points at, found by reading the file again (within :mod:`belvedere.bounded`'s caps)."""

from __future__ import annotations

from belvedere.bounded import LimitError, read_regular_text
from belvedere.errors import SourceLocation

__all__ = ["pinpoint"]


def pinpoint(near: SourceLocation | None, text: str, offset: int = 0) -> SourceLocation | None:
    """Where ``text[offset]`` is in the file, looking for ``text`` from ``near`` on (an
    element's start, say, to find the column of an expression in one of its attributes).

    Falls back to ``near`` when the file cannot be read or does not hold ``text`` as written
    (an attribute with entities, for instance)."""
    if near is None or near.line <= 0:
        return near
    try:
        source = read_regular_text(near.path)
    except (LimitError, ValueError):
        return near
    start = 0
    for _ in range(near.line - 1):
        start = source.find("\n", start) + 1
        if start == 0:
            return near
    start += max(0, near.col - 1)
    found = source.find(text, start)
    if found < 0:
        return near
    at = found + offset
    line_start = source.rfind("\n", 0, at) + 1
    return SourceLocation(near.path, source.count("\n", 0, at) + 1, at - line_start + 1)
