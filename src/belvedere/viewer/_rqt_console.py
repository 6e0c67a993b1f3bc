"""rqt_console in the browser: the ``/rosout`` stream as a table (severity, node, stamp,
message, location), newest first, with rqt_console's filters (severities, node, text), a
highlight, pause and clear."""

from __future__ import annotations

import html
import threading
from collections import deque
from typing import Any, Final

from belvedere.graph import SEVERITIES, LogFilter, LogRow, Node, log_row
from belvedere.viewer._tool_page import ToolPage

__all__ = ["ConsolePage"]

KEEP: Final = 20_000
"""Messages kept, the oldest dropped first (rqt_console's default buffer size)."""
SHOWN: Final = 300
"""Rows drawn in the page: the newest that pass the filters."""
QUEUE: Final = 1000
_ROW_COLOURS: Final = {4: "#fff3cd", 8: "#f8d7da", 16: "#f1b0b7"}
_HEAD: Final = (
    "<style>.rqt-log{border-collapse:collapse;font:12px monospace;width:100%}"
    ".rqt-log td,.rqt-log th{border:1px solid #ddd;padding:2px 4px;text-align:left;"
    "vertical-align:top}.rqt-log tr.hl td{outline:2px solid #1971c2;font-weight:bold}</style>"
    '<table class="rqt-log"><tr><th>#</th><th>Severity</th><th>Node</th><th>Stamp</th>'
    "<th>Message</th><th>Location</th></tr>"
)


class ConsolePage:
    """The ``/rosout`` messages of the graph ``node`` is on, on ``page``."""

    def __init__(self, node: Node, page: ToolPage, *, topic: str = "/rosout") -> None:
        self.page = page
        self.rows: deque[tuple[int, LogRow]] = deque(maxlen=KEEP)
        self.received = 0
        self.filter = LogFilter()
        self._lock = threading.Lock()
        self._dirty = True
        gui = page.gui
        self.paused = gui.add_checkbox("Pause", False)
        with gui.add_folder("Filters"):
            self.levels = {
                level: gui.add_checkbox(name.title(), True) for level, name in SEVERITIES.items()
            }
            self.node_text = gui.add_text("Node contains", "")
            self.message_text = gui.add_text("Message contains", "")
            self.highlight = gui.add_text("Highlight", "")
        for control in [*self.levels.values(), self.node_text, self.message_text, self.highlight]:
            control.on_update(lambda _: self._changed())
        gui.add_button("Clear").on_click(lambda _: self.clear())
        self.status = gui.add_markdown("")
        self.table = gui.add_html(_HEAD + "</table>")
        node.subscribe(topic, "rosgraph_msgs/Log", self._take, queue_size=QUEUE)
        page.start(self.refresh)

    def _changed(self) -> None:
        self.filter = LogFilter(
            levels=frozenset(level for level, box in self.levels.items() if box.value),
            node=self.node_text.value,
            text=self.message_text.value,
            highlight=self.highlight.value,
        )
        self._dirty = True

    def _take(self, msg: Any) -> None:
        row = log_row(msg)
        with self._lock:
            self.received += 1
            self.rows.append((self.received, row))
            self._dirty = True

    def clear(self) -> None:
        with self._lock:
            self.rows.clear()
            self._dirty = True

    def shown(self) -> list[tuple[int, LogRow]]:
        """The rows the filters pass, newest first, at most :data:`SHOWN`."""
        with self._lock:
            rows = list(self.rows)
        passing = [(n, row) for n, row in reversed(rows) if self.filter.shows(row)]
        return passing[:SHOWN]

    def _html(self, rows: list[tuple[int, LogRow]]) -> str:
        cells = []
        for number, row in rows:
            colour = _ROW_COLOURS.get(row.level)
            style = f' style="background:{colour}"' if colour else ""
            mark = ' class="hl"' if self.filter.highlights(row) else ""
            values = (number, row.severity, row.node, row.stamp, row.message, row.location)
            tds = "".join(f"<td>{html.escape(str(value))}</td>" for value in values)
            cells.append(f"<tr{mark}{style}>{tds}</tr>")
        return _HEAD + "".join(cells) + "</table>"

    def refresh(self) -> None:
        if not self._dirty or self.paused.value:
            return
        self._dirty = False
        rows = self.shown()
        self.table.content = self._html(rows)
        with self._lock:
            total = len(self.rows)
        self.status.content = f"Displaying {len(rows)} of {total} messages"

    def close(self) -> None:
        self.page.close()
