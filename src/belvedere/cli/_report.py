"""What the verbs print besides their data, and what ``-q`` and ``-v`` do to it, the same
on every verb.

By default: errors, warnings, notices (``note: …``, timings, what a verb assumed), and for
xacro's legacy unprefixed tags and macro calls one summary line per file read. ``-q`` drops
the notices and summaries (errors and warnings stay); ``-qq`` leaves errors only. ``-v``
lists each legacy tag and call with its file:line in place of the summary, and the
library's debug records.

Everything goes through the ``belvedere`` logger, whose level ``main()`` sets from
``-q``/``-v``: the library logs its own warnings (xacro on the ``xacro`` verb and in launch
files), and the verbs report the diagnostics a model keeps here.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from typing import TYPE_CHECKING

from belvedere.description.xacro import legacy_summary

if TYPE_CHECKING:
    from belvedere.description.urdf import Diagnostic

__all__ = ["notice", "report_diagnostics", "report_lines"]

logger = logging.getLogger("belvedere.cli")


def notice(text: str) -> None:
    """A line for the user that ``-q`` hides."""
    logger.info("%s", text)


def report_diagnostics(diagnostics: Iterable[Diagnostic], *, source: str) -> None:
    """A model's diagnostics on stderr, those about xacro's legacy syntax summed up in one line
    (at the first of them) for the file ``source`` that was read."""
    found = list(diagnostics)
    legacy = [(d.location, d.legacy) for d in found if d.legacy is not None]
    summary = None if logger.isEnabledFor(logging.DEBUG) else legacy_summary(source, legacy)
    for d in found:
        if d.legacy is not None:
            logger.debug("%s", d)
            if summary is not None:
                logger.info("%s", summary)
                summary = None
        elif d.severity == "error":
            logger.error("%s", d)
        elif d.severity == "note":
            notice(str(d))
        else:
            logger.warning("%s", d)


def report_lines(lines: Iterable[str]) -> None:
    """Lines that carry their own ``file:line: warning:`` or ``note:`` (a launch file's, a
    world's): notes are notices."""
    for line in lines:
        if ": note: " in line or line.startswith("note: "):
            notice(line)
        else:
            logger.warning("%s", line)
