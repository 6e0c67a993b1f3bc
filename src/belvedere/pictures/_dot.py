"""Graphviz's ``dot``: the layout every picture here is drawn with, run as a bounded program."""

from __future__ import annotations

import shutil
from pathlib import Path

from belvedere.bounded import run_bounded
from belvedere.errors import BelvedereError
from belvedere.fileio import write_file

__all__ = ["DotError", "render", "require_dot", "write_pictures"]

DOT_SECONDS = 30.0
"""A picture of a few hundred nodes takes dot well under a second; past this it is stuck."""
DOT_BYTES = 64 * 1024 * 1024


class DotError(BelvedereError):
    """Graphviz is missing or refused a graph."""


def require_dot() -> str:
    """Where ``dot`` is.

    Raises:
        DotError: it is not installed.
    """
    dot = shutil.which("dot")
    if dot is None:
        msg = "Graphviz's 'dot' is not installed: it lays out the graph pictures"
        raise DotError(msg, hint="install Debian's graphviz (apt-get install graphviz)")
    return dot


def render(gv: str, fmt: str) -> bytes:
    """``gv`` (Graphviz's language) laid out by ``dot`` as ``fmt`` (``svg``, ``pdf``, ``png``).

    Raises:
        DotError: ``dot`` is not installed, or it failed (its own message).
    """
    dot = require_dot()
    ran = run_bounded([dot, f"-T{fmt}"], seconds=DOT_SECONDS, limit=DOT_BYTES, stdin=gv.encode())
    if ran.status != 0 or ran.stopped:
        why = ran.stderr.decode(errors="replace").strip() or f"stopped ({ran.stopped})"
        msg = f"dot could not lay out the picture: {why}"
        raise DotError(msg)
    return ran.stdout


def write_pictures(gv: str, stem: Path | str) -> list[Path]:
    """``STEM.gv`` and ``STEM.pdf``, as urdf_to_graphiz and view_frames write them; the
    files written. The PDF is laid out first so a failure leaves neither."""
    pdf = render(gv, "pdf")
    base = Path(stem)
    gv_path = base.with_name(base.name + ".gv")
    pdf_path = base.with_name(base.name + ".pdf")
    return [write_file(gv_path, gv), write_file(pdf_path, pdf)]
