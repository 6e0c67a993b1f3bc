"""Argument handling shared by the verbs."""

from __future__ import annotations

from belvedere.description.xacro._command import split_mappings
from belvedere.errors import BelvedereError

__all__ = ["mappings_only"]


def mappings_only(extra: list[str]) -> dict[str, str]:
    """The ``name:=value`` arguments after the file; anything else is a usage error."""
    rest, mappings = split_mappings(extra)
    if rest:
        msg = f"unexpected arguments: {' '.join(rest)} (xacro args are written name:=value)"
        raise BelvedereError(msg)
    return mappings
