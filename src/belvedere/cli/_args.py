"""Argument handling shared by the verbs."""

from __future__ import annotations

import argparse

from belvedere.errors import BelvedereError
from belvedere.mappings import split_mappings

__all__ = ["add_viewer_options", "mappings_only", "origin", "worker_count"]


def origin(text: str) -> str:
    """An ``--allow-origin`` value, normalised (a usage error if it is no origin)."""
    from belvedere.access import check_origin

    try:
        return check_origin(text)
    except BelvedereError as err:
        raise argparse.ArgumentTypeError(err.message) from None


def add_viewer_options(p: argparse.ArgumentParser) -> None:
    """Where the viewer is served, and who may use it."""
    p.add_argument("--port", type=int, default=8080, help="viewer port (default: 8080)")
    p.add_argument(
        "--host",
        default="127.0.0.1",
        help="viewer address (default: this machine only; another address needs the token "
        "in the printed URL)",
    )
    p.add_argument(
        "--allow-origin",
        action="append",
        default=[],
        type=origin,
        dest="allow_origins",
        metavar="ORIGIN",
        help="also accept the viewer's websocket from pages of ORIGIN (scheme://host[:port]; "
        "repeatable; * for any): by default only the viewer's own page may connect",
    )


def mappings_only(extra: list[str]) -> dict[str, str]:
    """The ``name:=value`` arguments after the file; anything else is a usage error."""
    rest, mappings = split_mappings(extra)
    if rest:
        msg = f"unexpected arguments: {' '.join(rest)} (xacro args are written name:=value)"
        raise BelvedereError(msg)
    return mappings


def worker_count(text: str) -> int:
    """``--workers N``: a positive whole number."""
    value = int(text) if text.isdigit() else 0
    if value < 1:
        msg = f"--workers expects a positive whole number, got {text!r}"
        raise argparse.ArgumentTypeError(msg)
    return value
