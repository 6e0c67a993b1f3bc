"""rqt_plot in the browser: numeric fields of messages against the graph's time, on uPlot
(viser's, served with the page).

Every message is taken (a subscription with a deep queue; the callback only appends), and the
page is sent the samples in batches, ten times a second. The x axis is the message's header
stamp when it has one, else the graph's time on arrival: simulated time when the graph has
one, else seconds since the plot started. Series of different topics share the x axis of all
their samples, each holding its last value between its own.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Sequence
from typing import Any, Final

import numpy as np

from belvedere.errors import BelvedereError
from belvedere.graph import NS, GraphTopics, Node
from belvedere.msgs import FieldPathError, Series, field_value, resolve_series, split_plot_args
from belvedere.viewer._tool_page import ToolPage

__all__ = ["PlotPage"]

QUEUE: Final = 10_000
"""Messages a subscription holds before the executor takes them: at 100 Hz, 100 s of them."""
KEEP: Final = 50_000
"""Samples kept per series (rqt_plot keeps its buffer bounded too)."""
COLOURS: Final = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2")


class PlotPage:
    """Plots the fields the ``paths`` name (rqt_plot's arguments) as the graph publishes them.

    Paths whose topic nobody publishes yet wait for it, as rqt_plot does."""

    def __init__(self, node: Node, paths: Sequence[str], page: ToolPage) -> None:
        self.node = node
        self.page = page
        self.topics = GraphTopics(node.graph)
        self.pending: list[str] = []
        self.series: list[Series] = []
        self.samples: dict[Series, deque[tuple[float, float]]] = {}
        """Each series' (x seconds, value), oldest first."""
        self.received = 0
        """Messages taken from the subscriptions (every sample plotted comes from one)."""
        self._subscribed: dict[str, Any] = {}
        self._lock = threading.Lock()
        self._dirty = False
        self._origin_ns = 0 if node.graph.sim_time else node.now_ns()
        self.notes: list[str] = []
        gui = page.gui
        self.plot = gui.add_uplot(
            (np.zeros(0), np.zeros(0)),
            ({"label": "time (s)"}, {"label": "none"}),
            scales={"x": {"time": False}},  # seconds of the graph's time, not dates
            axes=({"label": "time (s)"}, {}),
            aspect=2.2,
        )
        self.paused = gui.add_checkbox("Pause", False)
        self.autoscroll = gui.add_checkbox("Autoscroll", True)
        self.window = gui.add_number("Window (s)", 10.0, min=0.5, max=3600.0, step=0.5)
        self.entry = gui.add_text("Topic", "")
        gui.add_button("Add").on_click(lambda _: self.add_text(self.entry.value))
        gui.add_button("Clear").on_click(lambda _: self.clear())
        self.status = gui.add_markdown("")
        for path in split_plot_args(paths):
            self.add(path)
        node.timer(0.5, self._look_for_topics)
        page.start(self.refresh)

    # --- series -------------------------------------------------------------------------------
    def add_text(self, text: str) -> None:
        """Add the paths a user typed (the page's Topic box); a bad one is noted, not raised."""
        for path in split_plot_args([text]):
            try:
                self.add(path)
            except BelvedereError as err:
                self.notes.append(err.message)
        self._dirty = True

    def add(self, path: str) -> None:
        """Plot ``path`` now if its topic is published, else once it is.

        Raises:
            FieldPathError: the topic's messages have no number there.
        """
        found = resolve_series(path, self.topics.published())
        if found is None:
            self.pending.append(path)
            return
        for series in found:
            if series not in self.samples:
                self._subscribe(series)

    def _look_for_topics(self) -> None:
        waiting, self.pending = self.pending, []
        for path in waiting:
            try:
                self.add(path)
            except FieldPathError as err:
                # the node runs already: its log says it, as rqt_plot's status line does
                self.node.logger.warning("%s", err.message)
                self.notes.append(err.message)
                self._dirty = True

    def _subscribe(self, series: Series) -> None:
        with self._lock:
            self.series.append(series)
            self.samples[series] = deque(maxlen=KEEP)
        if series.topic in self._subscribed:
            return

        def take(msg: Any, topic: str = series.topic) -> None:
            self._take(topic, msg)

        self._subscribed[series.topic] = self.node.subscribe(
            series.topic, series.msg_type, take, queue_size=QUEUE
        )
        self._dirty = True

    def _x(self, msg: Any) -> float:
        header = getattr(msg, "header", None)
        stamp = getattr(header, "stamp", None)
        if stamp is not None and (stamp.sec or stamp.nanosec):
            stamp_ns = int(stamp.sec) * NS + int(stamp.nanosec)
        else:
            stamp_ns = self.node.now_ns()
        return (stamp_ns - self._origin_ns) / NS

    def _take(self, topic: str, msg: Any) -> None:
        x = self._x(msg)
        with self._lock:
            self.received += 1
            for series in self.series:
                if series.topic == topic:
                    value = field_value(msg, series.steps)
                    if value is not None:
                        self.samples[series].append((x, value))
            self._dirty = True

    def clear(self) -> None:
        with self._lock:
            for kept in self.samples.values():
                kept.clear()
            self._dirty = True

    # --- the page -----------------------------------------------------------------------------
    def data(self) -> tuple[np.ndarray, ...]:
        """The x axis and one column per series, as uPlot takes them: the window's samples
        (the last ``Window`` seconds when autoscrolling), each series holding its last value
        between its samples."""
        with self._lock:
            kept = [list(self.samples[s]) for s in self.series]
        columns = [np.array(c, dtype=np.float64).reshape(-1, 2) for c in kept]
        if not columns:
            return (np.zeros(0), np.zeros(0))
        xs = np.unique(np.concatenate([c[:, 0] for c in columns]))
        if self.autoscroll.value and xs.size:
            xs = xs[xs >= xs[-1] - float(self.window.value)]
        ys = []
        for column in columns:
            if not column.size:
                ys.append(np.zeros(xs.size))
                continue
            at = np.clip(np.searchsorted(column[:, 0], xs, side="right") - 1, 0, None)
            ys.append(column[at, 1])
        return (xs, *ys)

    def refresh(self) -> None:
        if not self._dirty or self.paused.value:
            return
        self._dirty = False
        data = self.data()
        labels = [s.label for s in self.series] or ["none"]
        series = [{"label": "time (s)"}] + [
            {"label": label, "stroke": COLOURS[i % len(COLOURS)], "width": 2}
            for i, label in enumerate(labels)
        ]
        if len(self.plot.series) != len(series):
            self.plot.series = tuple(series)
        self.plot.data = data
        waiting = [f"waiting for {path}" for path in self.pending]
        counts = [f"{len(self.samples[s])} samples of {s.label}" for s in self.series]
        self.status.content = "  \n".join([*self.notes[-5:], *waiting, *counts])

    def close(self) -> None:
        self.page.close()
        self.topics.close()
