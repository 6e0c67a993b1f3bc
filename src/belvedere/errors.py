"""The error types every part of belvedere raises, and how they print.

All errors share the root :class:`BelvedereError`; the CLI turns any of them into one
``error: …`` line (plus context lines) and exit code 1. Errors about a place in a file carry a
:class:`SourceLocation` and print like a compiler::

    arm.xacro:42:5: error: unknown macro name: xacro:wheel
      in macro 'arm' called from robot.xacro:10:3
      included from robot.xacro:3:5
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from dataclasses import dataclass
from typing import NamedTuple

__all__ = ["BelvedereError", "ParseError", "SourceLocation", "did_you_mean"]


class SourceLocation(NamedTuple):
    """A place in a file: 1-based line and column; 0 means unknown.

    (A named tuple: parsers make one per element, so it must be cheap.)"""

    path: str
    """The file's path as the user gave it (or ``<string>`` for in-memory input)."""
    line: int = 0
    col: int = 0

    def __str__(self) -> str:
        if self.line <= 0:
            return self.path
        if self.col <= 0:
            return f"{self.path}:{self.line}"
        return f"{self.path}:{self.line}:{self.col}"


def did_you_mean(
    name: str, known: Iterable[str], *, most: int = 1, cutoff: float = 0.6, quote: bool = True
) -> str | None:
    """``did you mean 'x'?`` for the name in ``known`` closest to ``name`` (``'x' or 'y'``…:
    the ``most`` closest, closest first; unquoted with ``quote`` false, as graph names are
    written), or None if none is close."""
    close = difflib.get_close_matches(name, sorted(set(known)), n=most, cutoff=cutoff)
    if not close:
        return None
    return "did you mean " + " or ".join(repr(c) if quote else c for c in close) + "?"


class BelvedereError(Exception):
    """Root of every error belvedere raises on purpose (bad input, missing files, …)."""

    def __init__(self, message: str, *, hint: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.hint = hint

    def describe(self) -> str:
        """The full text the CLI prints: ``error: message`` and a hint."""
        text = f"error: {self.message}"
        if self.hint:
            text += f"\n  hint: {self.hint}"
        return text

    def __str__(self) -> str:
        return self.describe()


@dataclass(frozen=True, slots=True)
class TrailEntry:
    """One step of the include/macro trail that led to an error."""

    what: str
    """E.g. ``in macro 'arm' called from`` or ``included from``."""
    location: SourceLocation


class ParseError(BelvedereError):
    """An error at a place in a file, printed as ``file:line:col: error: message``."""

    def __init__(
        self,
        message: str,
        location: SourceLocation | None = None,
        *,
        hint: str | None = None,
        trail: list[TrailEntry] | None = None,
    ) -> None:
        super().__init__(message, hint=hint)
        self.location = location
        self.trail: list[TrailEntry] = list(trail or [])

    def locate(self, location: SourceLocation | None) -> None:
        """Set the location if none is known yet (the innermost place wins)."""
        if self.location is None and location is not None:
            self.location = location

    def add_trail(self, what: str, location: SourceLocation) -> None:
        """Append an outer step of the trail (call sites are added innermost first)."""
        self.trail.append(TrailEntry(what, location))

    def describe(self) -> str:
        head = f"{self.location}: error: " if self.location else "error: "
        lines = [head + self.message]
        lines.extend(_trail_lines(self.trail))
        if self.hint:
            lines.append(f"  hint: {self.hint}")
        return "\n".join(lines)


def _trail_lines(trail: list[TrailEntry], *, keep: int = 8) -> list[str]:
    """The trail, repeats folded (``N times``) and the middle of a very long one elided."""
    folded: list[tuple[TrailEntry, int]] = []
    for entry in trail:
        if folded and folded[-1][0] == entry:
            folded[-1] = (entry, folded[-1][1] + 1)
        else:
            folded.append((entry, 1))
    lines = [f"  {e.what} {e.location}" + (f" ({n} times)" if n > 1 else "") for e, n in folded]
    if len(lines) > 2 * keep:
        lines = [*lines[:keep], f"  … {len(lines) - 2 * keep} more …", *lines[-keep:]]
    return lines
