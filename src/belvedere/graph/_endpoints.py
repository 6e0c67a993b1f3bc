"""A node's ends on the graph: topics, publishers, subscriptions and service servers.

Inside one process messages pass as objects, never serialized: a publisher hands each one to
the topic's subscriptions, and to the transport when a process elsewhere wants it. These
classes see their node and its graph through :class:`EndpointNode` (the graph is made of
them, so they do not import it).
"""

from __future__ import annotations

import logging
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from dataclasses import replace as _replace
from typing import Any, Literal, Protocol

from belvedere.errors import BelvedereError
from belvedere.graph._errors import GraphError
from belvedere.graph._executor import Executor
from belvedere.msgs import message_from_data, short, types

__all__ = [
    "EndpointGraph",
    "EndpointNode",
    "Publisher",
    "SeqRule",
    "ServiceServer",
    "Subscription",
    "Topic",
    "TopicUse",
]

logger = logging.getLogger("belvedere.graph")


class _Sender(Protocol):
    """What a publisher needs of the graph's transport."""

    def send(self, topic: Topic, msg: Any, publisher: Publisher) -> None: ...


class EndpointGraph(Protocol):
    """What publishers and subscriptions use of their node's graph (a
    :class:`belvedere.graph.Graph`)."""

    @property
    def executor(self) -> Executor: ...
    @property
    def transport(self) -> _Sender | None: ...
    def on_executor_thread(self) -> bool: ...
    def clock_stamp(self) -> tuple[int, int]: ...
    def remove_publisher(self, pub: Publisher) -> None: ...
    def remove_subscription(self, sub: Subscription) -> None: ...
    def remove_service(self, server: ServiceServer) -> None: ...


class EndpointNode(Protocol):
    """What publishers, subscriptions and service servers (and those who hold them) use of
    their node (a :class:`belvedere.graph.Node`)."""

    @property
    def name(self) -> str: ...
    @property
    def full_name(self) -> str: ...
    @property
    def graph(self) -> EndpointGraph: ...
    @property
    def closed(self) -> bool: ...
    @property
    def seqs(self) -> dict[str, int]: ...
    @property
    def on_crash(self) -> Callable[[Exception], None] | None: ...
    @property
    def publishers(self) -> list[Publisher]: ...
    @property
    def subscriptions(self) -> list[Subscription]: ...
    @property
    def services(self) -> list[ServiceServer]: ...


@dataclass(eq=False)
class Topic:
    """One topic of the graph: its type and who is on it here."""

    name: str
    type: str
    publishers: list[Publisher] = field(default_factory=list)
    subscriptions: list[Subscription] = field(default_factory=list)
    latched: dict[Publisher, Any] = field(default_factory=dict)
    """The last message of each latching publisher (ROS 1 latches per publisher)."""
    remote: bool = False
    """A subscriber in another process wants this topic."""

    @property
    def has_header(self) -> bool:
        """Messages of this type start with a ``std_msgs/Header`` (whose ``seq`` publishers
        count up, as ROS 1's do)."""
        cached: bool | None = self.__dict__.get("_has_header")
        if cached is None:
            fields = getattr(types().cls(self.type), "__dataclass_fields__", {})
            field_ = fields.get("header")
            cached = field_ is not None and "Header" in str(field_.type)
            self.__dict__["_has_header"] = cached
        return cached


TopicUse = Literal["publish", "subscribe", "use"]

SeqRule = Literal["roscpp", "rospy", "given"]
"""How a publisher numbers ``header.seq``: roscpp from 0, counting every message published;
rospy from 1, counting only messages sent to a subscriber; given: as the message says (the
publisher numbered it)."""


class Publisher:
    """Publishes messages of one type on one topic."""

    def __init__(
        self,
        node: EndpointNode,
        topic: Topic,
        *,
        latch: bool,
        queue_size: int,
        seq_rule: SeqRule = "roscpp",
    ) -> None:
        self.node = node
        self.topic = topic
        self.latch = latch
        self.queue_size = queue_size
        self.seq_rule: SeqRule = seq_rule
        self.count = 0
        self.latched: tuple[int, Any] = (0, None)
        """A latching publisher's last message and its number (one object: a transport's
        thread reads both at once)."""

    @property
    def name(self) -> str:
        return self.topic.name

    @property
    def wanted(self) -> bool:
        """Would a message be delivered anywhere (or kept, when latched)? Publishers of costly
        messages check this first, so nobody listening costs nothing."""
        topic = self.topic
        return self.latch or bool(topic.subscriptions) or topic.remote

    def publish(self, msg: Any) -> None:
        """Send ``msg`` to every subscriber (a message object of the topic's type)."""
        topic = self.topic
        msgtype = getattr(msg, "__msgtype__", None)
        if msgtype != topic.type:
            got = short(msgtype) if msgtype else type(msg).__name__
            text = f"publishing {got} on {topic.name}, whose type is {short(topic.type)}"
            raise GraphError(text)
        graph = self.node.graph
        if not graph.on_executor_thread():
            graph.executor.post(lambda: self.publish(msg))
            return
        if self.node.closed:
            return  # its node was shut down: rospy's publish after shutdown goes nowhere too
        if topic.has_header and self.seq_rule != "given":
            msg = self._numbered(msg)
        self.count += 1
        if self.latch:
            topic.latched[self] = msg
            self.latched = (self.count, msg)
        for sub in topic.subscriptions:
            sub.enqueue(msg)
        transport = graph.transport
        if transport is not None and topic.remote:
            transport.send(topic, msg, self)

    def next_seq(self) -> int:
        """The ``header.seq`` the next message published here gets: a publisher that builds
        its message with it spares the copy :meth:`publish` otherwise makes to number it."""
        seq = self.node.seqs.get(self.topic.name, 0)
        return (seq + 1 if self.seq_rule == "rospy" else seq) & 0xFFFFFFFF

    def _numbered(self, msg: Any) -> Any:
        """``msg`` with the next ``header.seq`` of this node's publications on the topic (a
        copy: the caller's message and what other subscribers hold stay as they are)."""
        counters = self.node.seqs
        topic = self.topic
        if self.seq_rule == "rospy":
            if not (topic.subscriptions or topic.remote):
                return msg  # rospy numbers only what it sends
            seq = counters.get(topic.name, 0) + 1
            counters[topic.name] = seq
        else:
            seq = counters.get(topic.name, 0)
            counters[topic.name] = seq + 1
        header = msg.header
        if header.seq == seq:
            return msg
        return _replace(msg, header=_replace(header, seq=seq & 0xFFFFFFFF))

    def publish_data(self, data: Any = None) -> Any:
        """Publish a message built from YAML-like data (``{'linear': {'x': 0.2}}``)."""
        msg = message_from_data(self.topic.type, data, clock=self.node.graph.clock_stamp)
        self.publish(msg)
        return msg

    def unregister(self) -> None:
        self.node.graph.remove_publisher(self)


class Subscription:
    """Calls ``callback(msg)`` for each message on a topic, on the executor thread."""

    def __init__(
        self,
        node: EndpointNode,
        topic: Topic,
        callback: Callable[[Any], object],
        *,
        queue_size: int,
    ) -> None:
        self.node = node
        self.topic = topic
        self.callback = callback
        self.pending: deque[Any] = deque(maxlen=queue_size if queue_size > 0 else None)
        self._scheduled = False
        self.received = 0

    @property
    def name(self) -> str:
        return self.topic.name

    def enqueue(self, msg: Any) -> None:
        self.pending.append(msg)
        if not self._scheduled:
            self._scheduled = True
            self.node.graph.executor.ready(self)

    def deliver_one(self) -> bool:
        pending = self.pending
        if self.node.closed:
            pending.clear()
        if not pending:
            self._scheduled = False
            return False
        msg = pending.popleft()
        self.received += 1
        try:
            self.callback(msg)
        except BelvedereError as err:
            if self.node.on_crash is None:
                raise
            self.node.on_crash(err)
        except Exception:  # a user callback bug must not kill the graph
            logger.exception("callback of %s on %s failed", self.node.name, self.topic.name)
        if pending:
            return True
        self._scheduled = False
        return False

    def unregister(self) -> None:
        self.node.graph.remove_subscription(self)


class ServiceServer:
    """Answers requests of one service type with ``handler(request) -> response``."""

    def __init__(
        self,
        node: EndpointNode,
        name: str,
        srv_type: str,
        handler: Callable[[Any], Any],
        *,
        threaded: bool = False,
    ) -> None:
        self.node = node
        self.name = name
        self.type = srv_type
        self.handler = handler
        self.threaded = threaded
        """Calls from other processes run on a thread of their own, not the executor (rospy
        runs each request so: a handler may sleep or wait for messages)."""

    def handle(self, request: Any) -> Any:
        response = self.handler(request)
        expected = f"{self.type}_Response"
        if response is None:
            response = message_from_data(expected, None)
        elif isinstance(response, dict):
            response = message_from_data(expected, response)
        if getattr(response, "__msgtype__", None) != expected:
            msg = f"service {self.name} handler returned {response!r}, not a {short(expected)}"
            raise GraphError(msg)
        return response

    def unregister(self) -> None:
        self.node.graph.remove_service(self)
