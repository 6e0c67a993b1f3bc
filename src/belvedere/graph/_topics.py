"""The graph's topics and who publishes them, here and in other processes."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from belvedere.graph._graph import Graph
from belvedere.graph._zenoh import ZenohTransport
from belvedere.msgs import short

__all__ = ["GraphTopics"]


class GraphTopics:
    """Topics with a publisher and every topic's type: this process's from the graph, other
    processes' from their publishers' liveliness tokens. ``on_change`` is called (on Zenoh's
    thread) when another process's publisher comes or goes."""

    def __init__(self, graph: Graph, *, on_change: Callable[[], None] | None = None) -> None:
        self.graph = graph
        self.on_change = on_change
        self._remote: dict[str, set[tuple[str, str]]] = {}
        """topic → {(type, node)} of publishers in other processes"""
        self._lock = threading.Lock()
        self._watch: Any = None
        if isinstance(graph.transport, ZenohTransport):
            self._watch = graph.transport.watch_publishers(self._seen)

    def _seen(self, topic: str, type_name: str, node: str, alive: bool) -> None:
        with self._lock:
            kinds = self._remote.setdefault(topic, set())
            if alive:
                kinds.add((type_name, node))
            else:
                kinds.discard((type_name, node))
                if not kinds:
                    del self._remote[topic]
        if self.on_change is not None:
            self.on_change()

    def _remote_types(self) -> dict[str, str]:
        with self._lock:
            return {name: min(kinds)[0] for name, kinds in self._remote.items()}

    def published(self) -> dict[str, str]:
        """Every topic someone publishes now, with its type (this process's first)."""
        found = {name: t.type for name, t in list(self.graph.topics.items()) if t.publishers}
        for name, type_name in self._remote_types().items():
            found.setdefault(name, type_name)
        return found

    def type_of(self, topic: str) -> str | None:
        """The topic's type when anyone publishes or subscribes to it, else None."""
        local = self.graph.topics.get(topic)
        if local is not None and (local.publishers or local.subscriptions):
            return local.type
        return self._remote_types().get(topic)

    def of_type(self, msg_type: str) -> list[str]:
        """Topics someone publishes ``msg_type`` on (any type when empty)."""
        want = short(msg_type) if msg_type else None
        return sorted(
            name
            for name, type_name in self.published().items()
            if want is None or short(type_name) == want
        )

    def close(self) -> None:
        if self._watch is not None:
            self._watch.undeclare()
            self._watch = None
