"""The graph's topics and their types, here and in other processes, for the Displays panel."""

from __future__ import annotations

import threading
from typing import Any

from belvedere.graph import Graph, ZenohTransport
from belvedere.msgs import short

__all__ = ["GraphTopics"]


class GraphTopics:
    """Topics with a publisher (offered to displays) and every topic's type (to refuse a
    display of the wrong type)."""

    def __init__(self, graph: Graph) -> None:
        self.graph = graph
        self._remote: dict[str, dict[str, int]] = {}
        """topic → {type: publishers in other processes}"""
        self._lock = threading.Lock()
        self._watch: Any = None
        if isinstance(graph.transport, ZenohTransport):
            self._watch = graph.transport.watch_publishers(self._seen)

    def _seen(self, topic: str, type_name: str, _node: str, alive: bool) -> None:
        with self._lock:
            counts = self._remote.setdefault(topic, {})
            counts[type_name] = counts.get(type_name, 0) + (1 if alive else -1)
            if counts[type_name] <= 0:
                del counts[type_name]
            if not counts:
                del self._remote[topic]

    def type_of(self, topic: str) -> str | None:
        local = self.graph.topics.get(topic)
        if local is not None and (local.publishers or local.subscriptions):
            return local.type
        with self._lock:
            remote = sorted(self._remote.get(topic, ()))
        return remote[0] if remote else None

    def of_type(self, msg_type: str) -> list[str]:
        """Topics someone publishes ``msg_type`` on (any type when empty)."""
        want = short(msg_type) if msg_type else None
        found = {
            name
            for name, t in list(self.graph.topics.items())
            if t.publishers and (want is None or short(t.type) == want)
        }
        with self._lock:
            found |= {
                name
                for name, types in self._remote.items()
                if want is None or any(short(t) == want for t in types)
            }
        return sorted(found)

    def close(self) -> None:
        if self._watch is not None:
            self._watch.undeclare()
            self._watch = None
