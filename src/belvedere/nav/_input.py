"""Scans and poses are data, not trusted geometry: the checks the mappers, amcl and the
costmaps make before using a reading, and the counted warnings they give for what they drop.

A bag downloaded from the internet, or a node on the graph, can send anything a message's
fields hold. The rules, the same for every reader of ``LaserScan`` and odometry:

- A scan with more than :data:`~belvedere.bounded.SCAN_BEAMS` beams is skipped, as is one
  whose ``angle_min`` or ``angle_increment`` (or its last beam's angle) is not finite, or whose
  ``range_min`` or ``range_max`` is NaN, or whose ``range_max`` is not above ``range_min`` and 0
  (:func:`scan_problem`).
- NaN ranges are dropped and counted. ``+inf`` and ``-inf`` are not counted: REP 117 gives
  them a meaning (no return, too close), and real lasers send them all the time.
- A pose (odometry, a sensor's mount, an initial pose) with a value that is not finite or
  farther than :data:`~belvedere.bounded.POSE_METRES` from the origin is skipped
  (:func:`pose_problem`).
- A grid grown by input never passes :data:`~belvedere.bounded.GRID_CELLS` cells; the longest
  range a reader uses is what such a grid can hold around the sensor (:func:`grid_reach`).

Each cause is one :class:`Tally` line, counted: ``/slam_gmapping: dropped 12 NaN ranges in 3
scans``, never a line per message.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from belvedere.bounded import GRID_CELLS, POSE_METRES, SCAN_BEAMS

__all__ = [
    "Tally",
    "grid_reach",
    "laser_scan_problem",
    "plural",
    "pose_problem",
    "scan_problem",
]


def scan_problem(
    count: int, angle_min: float, angle_increment: float, range_min: float, range_max: float
) -> tuple[str, str] | None:
    """Why a scan of ``count`` beams with these fields cannot be used — (the reason, what
    exactly: ``("more than 65,536 beams", "5,000,000 beams")``) — or None when it can."""
    if count > SCAN_BEAMS:
        return f"more than {SCAN_BEAMS:,} beams", f"{count:,} beams"
    last = angle_min + max(count - 1, 0) * angle_increment
    for name, value in (
        ("angle_min", angle_min),
        ("angle_increment", angle_increment),
        ("last beam's angle", last),
    ):
        if not math.isfinite(value):
            return f"their {name} is not finite", f"{name} {value}"
    for name, value in (("range_min", range_min), ("range_max", range_max)):
        if math.isnan(value):
            return f"their {name} is nan", f"{name} {value}"
    if not range_max > max(range_min, 0.0):
        return "their range_max is not above range_min and 0", f"{range_min} .. {range_max}"
    return None


def laser_scan_problem(scan: Any) -> tuple[str, str] | None:
    """:func:`scan_problem` of a ``LaserScan`` (anything with its fields)."""
    return scan_problem(
        len(scan.ranges),
        float(scan.angle_min),
        float(scan.angle_increment),
        float(scan.range_min),
        float(scan.range_max),
    )


def pose_problem(values: Sequence[float]) -> tuple[str, str] | None:
    """Why a pose (x, y, yaw; or a translation and a rotation) cannot be used — (the reason,
    the pose) — or None: a value that is not finite, or farther than :data:`POSE_METRES`
    from zero."""
    for value in values:
        if not math.isfinite(value):
            return "not finite", f"({_numbers(values)})"
    for value in values:
        if abs(value) > POSE_METRES:
            return f"more than {POSE_METRES:g} m from the origin", f"({_numbers(values)})"
    return None


def _numbers(values: Sequence[float]) -> str:
    return ", ".join(f"{float(v):.6g}" for v in values)


def grid_reach(resolution: float, pad_cells: int = 0) -> float:
    """The longest range (m) a square grid of :data:`GRID_CELLS` cells of ``resolution``
    holds around a sensor at its centre, with ``pad_cells`` cells around the ends: a reader
    clips its usable range to this (a ``range_max`` of 1e30 becomes 144 m at 5 cm)."""
    side = math.isqrt(GRID_CELLS)
    return max(side // 2 - pad_cells - 2, 1) * resolution


def plural(count: int, noun: str) -> str:
    """``1 scan``, ``3 scans``, ``12,000 NaN ranges``."""
    return f"{count:,} {noun}" if count == 1 else f"{count:,} {noun}s"


@dataclass
class _Cause:
    events: int = 0
    items: int = 0
    first: str = ""
    logged: int = 0
    """The count of events last logged (0: never)."""


class Tally:
    """Counted warnings about input dropped or refused: one line per cause, not per message.

    ``add(template, …)`` counts one event of a cause; the template names it, with
    ``{count}`` for the events (``3 scans``, after ``noun``) and ``{items}`` for the items
    they held (``12 NaN ranges``, after ``item``). A live tally logs a cause when it first
    happens and again each time its count reaches ten times what was last logged (so a stream
    of bad messages costs a handful of lines); one that is not live logs nothing until
    :meth:`report`, which logs every cause once with its final count (``belvedere slam``).
    """

    def __init__(self, who: str, log: logging.Logger, *, live: bool = True) -> None:
        self.who = who
        self.log = log
        self.live = live
        self._causes: dict[tuple[str, str, str], _Cause] = {}

    def add(
        self,
        template: str,
        *,
        noun: str = "scan",
        first: str = "",
        items: int = 0,
        item: str = "",
    ) -> None:
        """One event of the cause ``template`` (with ``items`` items); ``first`` describes
        this event, shown if it is the cause's first (where and what exactly)."""
        key = (template, noun, item)
        cause = self._causes.get(key)
        if cause is None:
            cause = self._causes[key] = _Cause(first=first)
        cause.events += 1
        cause.items += items
        if self.live and cause.events >= max(10 * cause.logged, 1):
            cause.logged = cause.events
            self.log.warning("%s", self._line(key, cause, so_far=cause.events > 1))

    def refused(
        self,
        problem: tuple[str, str] | None,
        *,
        at: str,
        template: str = "skipped {count}: ",
        noun: str = "scan",
    ) -> bool:
        """Count ``problem`` (a :func:`scan_problem` or :func:`pose_problem`) under
        ``template`` followed by its reason, the event ``at`` a place; False if there is none."""
        if problem is None:
            return False
        why, what = problem
        self.add(template + why, noun=noun, first=f"{at}: {what}")
        return True

    def once(self, text: str) -> None:
        """A note, not counted: logged now (live) or by :meth:`report`, once per text."""
        key = (text, "", "")
        if key in self._causes:
            return
        cause = self._causes[key] = _Cause(events=1)
        if self.live:
            cause.logged = 1
            self.log.warning("%s", self._line(key, cause))

    def count(self, template: str, *, noun: str = "scan", item: str = "") -> int:
        """How many events of that cause were counted."""
        cause = self._causes.get((template, noun, item))
        return 0 if cause is None else cause.events

    def __bool__(self) -> bool:
        return bool(self._causes)

    def lines(self, *, who: bool = True) -> list[str]:
        """Every cause with its count so far, in the order they first happened (``who``:
        each line prefixed with whose tally it is)."""
        return [self._line(key, cause, who=who) for key, cause in self._causes.items()]

    def report(self) -> None:
        """Log each cause whose count changed since it was last logged."""
        for key, cause in self._causes.items():
            if cause.logged != cause.events:
                cause.logged = cause.events
                self.log.warning("%s", self._line(key, cause))

    def _line(
        self, key: tuple[str, str, str], cause: _Cause, *, so_far: bool = False, who: bool = True
    ) -> str:
        template, noun, item = key
        prefix = f"{self.who}: " if self.who and who else ""
        if not noun:  # a note (once)
            return prefix + template
        # (replaced, not str.format: the rest of the text may hold braces of its own)
        text = template.replace(
            "{count}", plural(cause.events, noun) + (" so far" if so_far else "")
        ).replace("{items}", plural(cause.items, item) if item else f"{cause.items:,}")
        if cause.first:
            text += f" (the first at {cause.first})"
        return prefix + text
