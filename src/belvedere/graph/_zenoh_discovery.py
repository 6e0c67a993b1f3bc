"""Who is on the graph, across processes, from Zenoh's liveliness tokens: nodes (a node whose
name another process takes later is shut down, as ROS 1's master does: "new node registered
with same name"), the publishers, subscribers and services of each topic, and the graph's
introspection (:class:`GraphInfo`).
"""

from __future__ import annotations

import contextlib
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import zenoh

from belvedere.graph._graph import Node
from belvedere.graph._zenoh_session import _Peer, decode_key, encode_key

__all__ = ["GraphInfo"]

logger = logging.getLogger("belvedere.transport")


class GraphInfo:
    """Who is on the graph, across processes (from liveliness tokens)."""

    def __init__(self) -> None:
        self.nodes: set[str] = set()
        self.publishers: dict[str, set[tuple[str, str]]] = {}
        """topic → {(type, node)}"""
        self.subscribers: dict[str, set[tuple[str, str]]] = {}
        self.services: dict[str, set[tuple[str, str]]] = {}
        self.processes: dict[str, set[str]] = {}
        """node → {``pid 1234 on host``} of the process(es) holding it"""

    def topic_type(self, topic: str) -> str | None:
        for table in (self.publishers, self.subscribers):
            for typ, _ in sorted(table.get(topic, ())):
                return typ
        return None


@dataclass(frozen=True, slots=True)
class _NodeHolder:
    """A process holding a node name, from its liveliness token."""

    zid: str
    process: str
    """``pid 1234 on host``"""
    since_ns: int
    """When it took the name (wall clock): the later one wins."""


class _Discovery(_Peer):
    """The transport's liveliness: its nodes' names, and who else is on the graph."""

    _process: str
    _own_nodes: dict[str, tuple[int, Node]]
    _clashes: set[tuple[str, str]]

    # --- nodes ---------------------------------------------------------------------------------
    def node_added(self, node: Node) -> None:
        # Who holds the name already? Asked before our token exists: once it does, they
        # start shutting their node down (a round trip of well under a millisecond here).
        holders = self._holders(node.full_name)
        since = time.time_ns()
        with self._lock:
            self._own_nodes[node.full_name] = (since, node)
        who = encode_key(self._process.removeprefix("pid ").replace(" on ", "@"))
        self._token("node", node.full_name, extra=(who, str(since)))
        for sample in holders:
            self._on_node_token(sample)

    def node_removed(self, node: Node) -> None:
        with self._lock:
            mine = self._own_nodes.get(node.full_name)
            if mine is not None and mine[1] is node:
                del self._own_nodes[node.full_name]
        self._drop_token("node", node.full_name)

    def _holders(self, name: str) -> list[Any]:
        """The liveliness tokens of processes holding node ``name``."""
        key = self._key("g/node/", encode_key(name) + "/**")
        with contextlib.suppress(zenoh.ZError):
            replies = self.session.liveliness().get(key, timeout=2.0)
            return [reply.ok for reply in replies if reply.ok is not None]
        return []

    def _on_node_token(self, sample: Any) -> None:
        """A process holds a node name: if it is one of ours, the later one keeps it."""
        if sample.kind != zenoh.SampleKind.PUT:
            return
        chunks = str(sample.key_expr).removeprefix(self._key("g/node/")).split("/")
        if len(chunks) != 4 or chunks[1] == self._zid:
            return
        name, zid, who, since = decode_key(chunks[0]), chunks[1], decode_key(chunks[2]), chunks[3]
        pid, _, host = who.partition("@")
        other = _NodeHolder(zid, f"pid {pid} on {host}", int(since) if since.isdigit() else 0)
        with self._lock:
            mine = self._own_nodes.get(name)
            if mine is None or (name, zid) in self._clashes:
                return
            self._clashes.add((name, zid))
            since_ns, node = mine
            ours_is_newer = (since_ns, self._zid) > (other.since_ns, other.zid)
            if not ours_is_newer:
                del self._own_nodes[name]
        if ours_is_newer:
            logger.warning(
                "node %s (%s) replaces the node of that name in %s, which is shut down, "
                "as in ROS 1",
                name,
                self._process,
                other.process,
            )
            return
        logger.warning(
            "node %s (%s) was replaced by a new node of that name in %s: shutting it down "
            "here, as in ROS 1",
            name,
            self._process,
            other.process,
        )
        graph = self.graph
        if graph is not None:
            graph.executor.post(node.shutdown)

    def watch_publishers(self, callback: Callable[[str, str, str, bool], None]) -> Any:
        """Call ``callback(topic, type, node, alive)`` for each publisher in other processes,
        those there now and each that comes (alive) or goes. Returns the watch."""
        prefix = self._key("g/pub/")
        own = self._zid

        def on_token(sample: Any) -> None:
            chunks = str(sample.key_expr).removeprefix(prefix).split("/")
            if len(chunks) != 4 or chunks[3] == own:
                return
            topic, type_name, node = (decode_key(c) for c in chunks[:3])
            callback(topic, type_name, node, sample.kind == zenoh.SampleKind.PUT)

        return self.session.liveliness().declare_subscriber(prefix + "**", on_token, history=True)

    def topic_users(self, topic: str, timeout: float = 2.0) -> list[tuple[str, str, str]]:
        """(``pub`` or ``sub``, type, node) of each publisher and subscriber of ``topic`` in
        other processes (a liveliness query: well under a millisecond on loopback)."""
        prefix = self._key("g/")
        key = self._key("g/*/", encode_key(topic) + "/**")
        found: list[tuple[str, str, str]] = []
        with contextlib.suppress(zenoh.ZError):
            for reply in self.session.liveliness().get(key, timeout=timeout):
                if reply.ok is None:
                    continue
                chunks = str(reply.ok.key_expr).removeprefix(prefix).split("/")
                if len(chunks) == 5 and chunks[0] in ("pub", "sub") and chunks[4] != self._zid:
                    found.append((chunks[0], decode_key(chunks[2]), decode_key(chunks[3])))
        return found

    def publisher_nodes(self, topic: str, timeout: float = 0.5) -> set[str]:
        """The nodes (in any process, this one too) that publish on ``topic``."""
        key = self._key("g/pub/", encode_key(topic) + "/**")
        prefix = self._key("g/pub/")
        nodes: set[str] = set()
        with contextlib.suppress(zenoh.ZError):
            for reply in self.session.liveliness().get(key, timeout=timeout):
                if reply.ok is not None:
                    chunks = str(reply.ok.key_expr).removeprefix(prefix).split("/")
                    if len(chunks) == 4:
                        nodes.add(decode_key(chunks[2]))
        return nodes

    def service_offered(self, name: str, timeout: float = 1.0) -> bool:
        """Does a node in another process offer service ``name``?"""
        key = self._key("g/srv/", encode_key(name) + "/**")
        with contextlib.suppress(zenoh.ZError):
            replies = self.session.liveliness().get(key, timeout=timeout)
            return any(reply.ok is not None for reply in replies)
        return False

    # --- introspection -------------------------------------------------------------------------
    def info(self, timeout: float = 1.0) -> GraphInfo:
        info = GraphInfo()
        tokens = self._key("g/")
        for reply in self.session.liveliness().get(tokens + "**", timeout=timeout):
            if reply.ok is None:
                continue
            chunks = str(reply.ok.key_expr).removeprefix(tokens).split("/")
            kind, names = chunks[0], [decode_key(c) for c in chunks[1:]]
            if kind == "node" and len(names) == 4:
                info.nodes.add(names[0])
                pid, _, host = names[2].partition("@")
                info.processes.setdefault(names[0], set()).add(f"pid {pid} on {host}")
            elif kind in ("pub", "sub", "srv") and len(names) == 4:
                table = {"pub": info.publishers, "sub": info.subscribers, "srv": info.services}[
                    kind
                ]
                table.setdefault(names[0], set()).add((names[1], names[2]))
                info.nodes.add(names[2])
        return info
