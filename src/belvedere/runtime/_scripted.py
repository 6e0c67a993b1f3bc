"""Scripted runs: messages published once at start, latched (``--pub 'TOPIC TYPE YAML'``),
and topics printed as ``belvedere topic echo`` prints them (``--echo TOPIC``), on a node of
their own beside a session's nodes."""

from __future__ import annotations

import sys
import threading
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph import (
    Graph,
    GraphTopics,
    Node,
    ZenohTransport,
    did_you_mean,
    resolve_name,
)
from belvedere.msgs import message_from_args, message_to_yaml, types

__all__ = ["EchoWait", "ScriptOptions", "install_script"]


@dataclass(frozen=True)
class ScriptOptions:
    """A scripted run's messages to publish and topics to print, checked."""

    pubs: tuple[tuple[str, str, Any], ...] = ()
    """(topic, message type, message) for each message published at start."""
    echoes: tuple[str, ...] = ()
    """The resolved topics printed to stdout."""

    @classmethod
    def parse(
        cls, pubs: Iterable[str], echoes: Iterable[str], *, duration: float | None = None
    ) -> ScriptOptions:
        """Check every ``pubs`` spec (``'TOPIC TYPE YAML'``: bad YAML fails here, before
        anything starts), each topic of ``echoes``, and the run's ``duration`` (seconds of
        simulated time; None: until stopped)."""
        if duration is not None and not duration > 0:
            msg = f"--duration expects a positive number of seconds, got {duration!r}"
            raise BelvedereError(msg)
        parsed = []
        for spec in pubs:
            words = spec.split(None, 2)
            if len(words) < 2:
                msg = f"--pub expects 'TOPIC TYPE YAML', got {spec!r}"
                raise BelvedereError(
                    msg, hint="e.g. --pub '/cmd_vel geometry_msgs/Twist {linear: {x: 0.2}}'"
                )
            try:
                topic, type_name = resolve_name(words[0]), types().resolve(words[1])
                msg_obj = message_from_args(type_name, words[2:])
            except BelvedereError as err:
                msg = f"--pub {spec!r}: {err.message}"
                raise BelvedereError(msg, hint=err.hint) from None
            parsed.append((topic, type_name, msg_obj))
        return cls(tuple(parsed), tuple(resolve_name(t) for t in echoes))


def install_script(
    graph: Graph,
    options: ScriptOptions,
    *,
    name: str = "belvedere_script",
    learns_topics: bool = False,
) -> EchoWait | None:
    """Add the ``--pub`` publishers and ``--echo`` printers to ``graph`` as a node of their own,
    ``name`` (none when there are neither).

    Echo subscriptions are made first, so they see the start-up messages too; a topic nobody
    publishes gets its type from the first ``--pub`` of it. ``learns_topics``: the run has
    nodes whose topics are known only once they advertise them (a script's process, a graph
    joined): an echoed topic not known yet is waited for (the :class:`EchoWait` returned);
    else it is refused here, before the run, as a misspelt name."""
    if not options.pubs and not options.echoes:
        return None
    node = graph.create_node(name)
    published_types = {topic: type_name for topic, type_name, _ in options.pubs}
    later: list[str] = []
    for topic in options.echoes:
        existing = graph.topics.get(topic)
        type_name = existing.type if existing else published_types.get(topic)
        if type_name is None:
            if learns_topics and isinstance(graph.transport, ZenohTransport):
                later.append(topic)
                continue
            msg = f"--echo {topic}: no node in this run publishes or subscribes to it"
            known = {n for n, t in graph.topics.items() if t.publishers or t.subscriptions}
            hint = did_you_mean(topic, known | set(published_types))
            raise BelvedereError(
                msg, hint=hint or "check the topic name (see 'belvedere topic list')"
            )
        node.subscribe(topic, type_name, _printer(_label(topic, options)), queue_size=0)
    for topic, type_name, msg_obj in options.pubs:
        pub = node.publisher(topic, type_name, latch=True)
        pub.publish(msg_obj)
    if not later:
        return None
    return EchoWait(node, {topic: _label(topic, options) for topic in later})


class EchoWait:
    """``--echo`` topics no node had advertised when the run started (a script's, whose
    process advertises it once running): each is subscribed to when a publisher of it
    appears, with its type, as ``topic echo`` waits for a topic to appear."""

    def __init__(self, node: Node, pending: dict[str, str | None]) -> None:
        self.node = node
        self._pending = pending
        """topic → the label its messages start with"""
        self._lock = threading.Lock()
        # the watch's first calls (publishers already there) may come before this is set
        self._topics: GraphTopics | None = None
        self._topics = GraphTopics(node.graph, on_change=self._changed)
        node.graph.executor.post(self._subscribe)

    def _changed(self) -> None:
        self.node.graph.executor.post(self._subscribe)  # on Zenoh's thread: subscribe on ours

    def _subscribe(self) -> None:
        topics = self._topics
        if topics is None or self.node.closed:
            return
        with self._lock:
            for topic, label in list(self._pending.items()):
                type_name = topics.type_of(topic)
                if type_name is not None:
                    del self._pending[topic]
                    self.node.subscribe(topic, type_name, _printer(label), queue_size=0)

    def close(self) -> list[str]:
        """Stop waiting; the topics no publisher of appeared (in time for ``--duration``)."""
        if self._topics is not None:
            self._topics.close()
            self._topics = None
        with self._lock:
            return sorted(self._pending)


def _label(topic: str, options: ScriptOptions) -> str | None:
    return topic if len(options.echoes) > 1 else None


def _printer(label: str | None) -> Any:
    """Prints as ``topic echo``; with several topics each message starts ``# TOPIC``."""
    prefix = f"# {label}\n" if label else ""

    def show(msg: Any) -> None:
        sys.stdout.write(prefix + message_to_yaml(msg) + "\n---\n")

    return show
