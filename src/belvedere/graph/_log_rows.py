"""``/rosout`` messages as rqt_console lists them: one row each (severity, node, stamp,
message, ``file:function:line``), and the filters it offers — severities, node, text —
with the rows a highlight picks out."""

from __future__ import annotations

import dataclasses
from collections.abc import Collection
from typing import Any, Final

from belvedere.graph._log import DEBUG, ERROR, FATAL, INFO, LEVEL_NAMES, WARN

__all__ = ["SEVERITIES", "LogFilter", "LogRow", "log_row"]

SEVERITIES: Final = {level: LEVEL_NAMES[level] for level in (DEBUG, INFO, WARN, ERROR, FATAL)}
"""rosgraph_msgs/Log's levels, lowest first, with their names."""


@dataclasses.dataclass(frozen=True, slots=True)
class LogRow:
    """One ``rosgraph_msgs/Log`` as a row of rqt_console's table."""

    level: int
    node: str
    stamp_ns: int
    message: str
    location: str
    """``file:function:line`` as rqt_console's Location column shows it."""
    topics: tuple[str, ...]

    @property
    def severity(self) -> str:
        return LEVEL_NAMES.get(self.level, str(self.level))

    @property
    def stamp(self) -> str:
        """``secs.nsecs`` as rqt_console prints a stamp."""
        sec, nsec = divmod(self.stamp_ns, 1_000_000_000)
        return f"{sec}.{nsec:09d}"


def log_row(msg: Any) -> LogRow:
    """The row of one ``rosgraph_msgs/Log``."""
    stamp = msg.header.stamp
    return LogRow(
        level=int(msg.level),
        node=str(msg.name),
        stamp_ns=int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec),
        message=str(msg.msg),
        location=f"{msg.file}:{msg.function}:{msg.line}",
        topics=tuple(str(t) for t in msg.topics),
    )


@dataclasses.dataclass(slots=True)
class LogFilter:
    """What rqt_console shows: rows of the chosen severities whose node and message contain
    the texts given (case-insensitive; empty: any); ``highlight`` marks the rows whose message
    contains it."""

    levels: Collection[int] = frozenset(SEVERITIES)
    node: str = ""
    text: str = ""
    highlight: str = ""

    def shows(self, row: LogRow) -> bool:
        return (
            row.level in self.levels
            and self.node.lower() in row.node.lower()
            and self.text.lower() in row.message.lower()
        )

    def highlights(self, row: LogRow) -> bool:
        return bool(self.highlight) and self.highlight.lower() in row.message.lower()
