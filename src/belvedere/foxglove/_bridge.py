"""The bridge: topics become channels, a client's subscription becomes the graph's.

Three threads meet here. The server's loop tells the bridge what clients ask (a client
subscribes, publishes, asks for parameters); the graph delivers messages on its executor
thread; the bridge's own thread turns them into ROS 1 bytes, hands them to the server and
keeps the channel list in step with the graph. The executor only appends to a queue, so a
simulation is not slowed by serialization for Foxglove.

Who may connect is :mod:`belvedere.access`'s rules: web pages of this machine, Foxglove's
web app (:data:`FOXGLOVE_APP`) and the origins given with ``--allow-origin``; clients that
are no web page (Foxglove's desktop app, scripts) send no ``Origin`` and pass. Served beyond
this machine, a client also needs the run's token (``ws://HOST:PORT/?token=…``, printed).
"""

from __future__ import annotations

import itertools
import logging
import re
import threading
import time
from collections import deque
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from functools import cache, partial
from typing import Any, Final

from belvedere.access import AccessError, ServerAccess
from belvedere.errors import BelvedereError
from belvedere.foxglove._inbound import ClientPublishing, Parameters
from belvedere.foxglove._protocol import ClientChannel
from belvedere.foxglove._server import ChannelInfo, Server
from belvedere.graph import Graph, GraphTopics, Node, Subscription
from belvedere.msgs import MessageTypeError, types

__all__ = [
    "DEFAULT_PORT",
    "FOXGLOVE_APP",
    "MESSAGE_ENCODING",
    "SCHEMA_ENCODING",
    "FoxgloveBridge",
    "FoxgloveBridgeError",
    "ros1_schema",
]

logger = logging.getLogger("belvedere.foxglove")

DEFAULT_PORT: Final = 8765
"""Foxglove's usual port (foxglove_bridge's default)."""
MESSAGE_ENCODING: Final = "ros1"
SCHEMA_ENCODING: Final = "ros1msg"
QUEUE: Final = 2000
"""Messages waiting for the bridge's thread; past this the oldest are dropped (a client far
behind the graph sees the newest, as a ROS subscriber with a full queue does)."""
SUBSCRIPTION_QUEUE: Final = 100
POLL_S: Final = 0.5
"""Wall seconds between looks at the topics of this process (other processes' publishers
are announced at once)."""
TIME_PERIOD_S: Final = 0.05
"""Wall seconds between broadcasts of the graph's time (when it moved)."""
FOXGLOVE_APP: Final = "https://app.foxglove.dev"
"""Foxglove's web app: trusted by default, as the app the bridge is for."""
CAPABILITIES: Final = ("time", "clientPublish", "parameters", "parametersSubscribe")


class FoxgloveBridgeError(BelvedereError):
    """The bridge cannot start as asked (the port taken, a bad origin)."""


@cache
def ros1_schema(msgtype: str) -> tuple[str, str]:
    """(ROS 1 type name, full definition) of a store type: the ``ros1msg`` schema, as
    ROS 1 bags' connections carry it (the type's text, then each type it uses)."""
    from belvedere.ros1 import message_class

    cls = message_class(msgtype)
    return str(cls._type), str(cls._full_text)


@dataclass(eq=False)
class _Channel:
    """A topic advertised to the clients."""

    topic: str
    msgtype: str
    id: int
    clients: set[int] = field(default_factory=set)
    """Clients subscribed to it."""
    subscription: Subscription | None = None
    """The graph's subscription (executor thread), while a client is subscribed."""
    closed: bool = False


class FoxgloveBridge:
    """Serves ``graph``'s topics to Foxglove clients on ``host:port`` (0: any free port).

    ``node_name``: the bridge's node on the graph. Stop with :meth:`close`. ``allow_origins``:
    web origins trusted besides this machine's pages and :data:`FOXGLOVE_APP`; ``token``: what
    a client must show (default: a new one when ``host`` is not loopback, none when it is; it
    is in :attr:`url`).
    """

    def __init__(
        self,
        graph: Graph,
        *,
        host: str = "127.0.0.1",
        port: int = DEFAULT_PORT,
        node_name: str = "foxglove_bridge",
        node: Node | None = None,
        topic_whitelist: Sequence[str] = (".*",),
        poll: float = POLL_S,
        allow_origins: Iterable[str] = (),
        token: str | None = None,
    ) -> None:
        """``node``: the bridge's node, when one exists already (a launch file's); else one
        named ``node_name`` is made. ``topic_whitelist``: regular expressions, one of which
        must match a topic's whole name for it to be served (foxglove_bridge's parameter)."""
        try:
            self.access = ServerAccess(
                host,
                what="Foxglove bridge",
                allow_origins=allow_origins,
                default_origins=[FOXGLOVE_APP],
                local_pages=True,
                token=token,
            )
        except AccessError as err:
            raise FoxgloveBridgeError(err.message) from None
        try:
            self._whitelist = [re.compile(pattern) for pattern in topic_whitelist]
        except re.error as err:
            msg = f"topic_whitelist: {err.pattern!r} is not a regular expression ({err})"
            raise FoxgloveBridgeError(msg) from None
        self.graph = graph
        self.node = node if node is not None else graph.create_node(node_name)
        self.sent = 0
        """Messages handed to the SDK so far."""
        self.dropped = 0
        """Messages dropped because the bridge fell ``QUEUE`` behind."""
        self._poll = poll
        self._lock = threading.Lock()
        self._channels: dict[str, _Channel] = {}
        self._by_id: dict[int, _Channel] = {}
        """Other processes' publishers: topic → {(type, node)}."""
        self._skipped: set[tuple[str, str]] = set()
        self._outbox: deque[tuple[_Channel, int, Any]] = deque()
        self._ids = itertools.count(1)
        self._wake = threading.Event()
        self._dirty = threading.Event()
        self._stop = threading.Event()
        self._publishing = ClientPublishing(self.node)
        self._params = Parameters(graph)
        try:
            self.server = Server(
                _Listener(self),
                host=host,
                port=port,
                access=self.access,
                name="belvedere",
                capabilities=CAPABILITIES,
                encodings=ClientPublishing.ENCODINGS,
            )
        except OSError as err:
            msg = f"cannot serve Foxglove on {host}:{port}: {err.strerror or err}"
            self._leave()
            raise FoxgloveBridgeError(
                msg, hint="choose another port: --foxglove PORT (0: any free one)"
            ) from None
        self._publishing.status = self.server.status
        self.host = host
        self.port = self.server.port
        self._topics = GraphTopics(graph, on_change=self._publishers_changed)
        self._refresh()
        self._thread = threading.Thread(target=self._run, name="belvedere-foxglove", daemon=True)
        self._thread.start()

    @property
    def url(self) -> str:
        """``ws://host:port`` (``/?token=…`` when it needs one): what Foxglove's "Open
        connection" asks for."""
        host = f"[{self.host}]" if ":" in self.host else self.host
        base = f"ws://{host}:{self.port}"
        return f"{base}/?token={self.access.token}" if self.access.token else base

    def topics(self) -> dict[str, str]:
        """The advertised topics and their types (the store's names)."""
        with self._lock:
            return {t: c.msgtype for t, c in self._channels.items()}

    def close(self) -> None:
        """Stop serving and leave the graph."""
        if self._stop.is_set():
            return
        self._stop.set()
        self._wake.set()
        self._thread.join(timeout=5.0)
        self._topics.close()
        self.server.stop()
        with self._lock:
            channels = list(self._channels.values())
            self._channels.clear()
            self._by_id.clear()
        for ch in channels:
            ch.closed = True
        self._leave()

    def _leave(self) -> None:
        node = self.node
        graph = self.graph
        if graph.executor.thread is None or graph.executor.stopped:
            node.shutdown()
        else:
            graph.executor.post(node.shutdown)

    # --- the graph's topics ----------------------------------------------------------------
    def _publishers_changed(self) -> None:
        """Zenoh's thread: another process's publisher came or went."""
        self._dirty.set()
        self._wake.set()

    def _wanted(self) -> dict[str, str]:
        """Every topic someone publishes now, with its type."""
        found: dict[str, str] = {}
        for name, type_name in self._topics.published().items():
            if not any(pattern.fullmatch(name) for pattern in self._whitelist):
                continue
            try:
                found[name] = types().resolve(type_name)
            except MessageTypeError:
                self._skip(name, type_name, "its type is unknown here")
        return found

    def _refresh(self) -> None:
        """Advertise the topics that appeared, withdraw those that went (own thread)."""
        wanted = self._wanted()
        with self._lock:
            gone = [c for t, c in self._channels.items() if wanted.get(t) != c.msgtype]
            for ch in gone:
                del self._channels[ch.topic]
            new = {t: m for t, m in wanted.items() if t not in self._channels}
        for ch in gone:
            self._withdraw(ch)
        for name, msgtype in sorted(new.items()):
            self._advertise(name, msgtype)

    def _advertise(self, topic: str, msgtype: str) -> None:
        try:
            name, text = ros1_schema(msgtype)
        except BelvedereError as err:
            self._skip(topic, msgtype, err.message)
            return
        ch = _Channel(topic, msgtype, next(self._ids))
        with self._lock:
            self._channels[topic] = ch
            self._by_id[ch.id] = ch
        self.server.add_channel(
            ChannelInfo(ch.id, topic, MESSAGE_ENCODING, name, text, SCHEMA_ENCODING)
        )
        logger.debug("foxglove: advertised %s [%s]", topic, name)

    def _withdraw(self, ch: _Channel) -> None:
        ch.closed = True
        ch.clients.clear()
        self.server.remove_channel(ch.id)
        with self._lock:
            self._by_id.pop(ch.id, None)
        self.graph.executor.post(partial(self._unsubscribe, ch))
        logger.debug("foxglove: withdrew %s", ch.topic)

    def _skip(self, topic: str, msgtype: str, why: str) -> None:
        if (topic, msgtype) not in self._skipped:
            self._skipped.add((topic, msgtype))
            logger.warning("foxglove: not serving %s: %s", topic, why)

    # --- clients' subscriptions (SDK threads, then the executor) -----------------------------
    def subscribed(self, client: int, channel: int) -> None:
        with self._lock:
            ch = self._by_id.get(channel)
            if ch is None:
                return
            ch.clients.add(client)
        # Subscribing again when another client is subscribed gives the newcomer what
        # latching publishers hold (the others see those once more).
        self.graph.executor.post(partial(self._subscribe, ch))

    def unsubscribed(self, client: int, channel: int) -> None:
        with self._lock:
            ch = self._by_id.get(channel)
            if ch is None:
                return
            ch.clients.discard(client)
        self.graph.executor.post(partial(self._unsubscribe, ch))

    def _subscribe(self, ch: _Channel) -> None:
        if ch.closed or not ch.clients:
            return
        if ch.subscription is not None:
            ch.subscription.unregister()
            ch.subscription = None
        try:
            ch.subscription = self.node.subscribe(
                ch.topic, ch.msgtype, partial(self._received, ch), queue_size=SUBSCRIPTION_QUEUE
            )
        except BelvedereError as err:
            logger.warning("foxglove: cannot subscribe to %s: %s", ch.topic, err.message)

    def _unsubscribe(self, ch: _Channel) -> None:
        if ch.subscription is not None and (ch.closed or not ch.clients):
            ch.subscription.unregister()
            ch.subscription = None

    def _received(self, ch: _Channel, msg: Any) -> None:
        """Executor thread: queue it, stamped with the graph's time now."""
        if ch.closed:
            return
        outbox = self._outbox
        if len(outbox) >= QUEUE:
            outbox.popleft()
            self.dropped += 1
        outbox.append((ch, self.graph.now_ns(), msg))
        self._wake.set()

    # --- the bridge's thread -------------------------------------------------------------------
    def _run(self) -> None:
        last_poll = time.monotonic()
        last_time = 0.0
        told = -1
        while not self._stop.is_set():
            self._wake.wait(timeout=TIME_PERIOD_S)
            self._wake.clear()
            try:
                self._send()
                now = time.monotonic()
                if self._dirty.is_set() or now - last_poll >= self._poll:
                    self._dirty.clear()
                    last_poll = now
                    self._refresh()
                if now - last_time >= TIME_PERIOD_S:
                    graph_ns = self.graph.now_ns()
                    if graph_ns != told:
                        self.server.broadcast_time(graph_ns)
                        told = graph_ns
                    last_time = now
            except Exception:  # the bridge keeps serving; the cause is logged
                logger.exception("foxglove: bridge error")

    def _send(self) -> None:
        serialize = types().store.serialize_ros1
        outbox = self._outbox
        batch: list[tuple[int, int, bytes]] = []
        while outbox:
            try:
                ch, stamp, msg = outbox.popleft()
            except IndexError:
                break
            if ch.closed:
                continue
            try:
                batch.append((ch.id, stamp, bytes(serialize(msg, ch.msgtype))))
            except Exception as err:  # noqa: BLE001 (a publisher's bad message skips itself)
                self._skip(ch.topic, ch.msgtype, f"a message does not serialize ({err})")
        if batch:
            self.server.log(batch)
            self.sent += len(batch)


class _Listener:
    """The server's listener: what clients ask, passed on (the server's loop, or a worker
    thread for parameters)."""

    def __init__(self, bridge: FoxgloveBridge) -> None:
        self.bridge = bridge

    def on_subscribe(self, client: int, channel: int) -> None:
        self.bridge.subscribed(client, channel)

    def on_unsubscribe(self, client: int, channel: int) -> None:
        self.bridge.unsubscribed(client, channel)

    def on_client_advertise(self, client: int, channel: ClientChannel) -> None:
        self.bridge._publishing.advertise(client, channel)

    def on_client_unadvertise(self, client: int, channel: int) -> None:
        self.bridge._publishing.unadvertise(client, channel)

    def on_client_message(self, client: int, channel: int, data: bytes) -> None:
        self.bridge._publishing.message(client, channel, data)

    def get_parameters(self, names: Sequence[str]) -> list[dict[str, Any]]:
        return self.bridge._params.get(names)

    def set_parameters(
        self, parameters: Sequence[tuple[str, Any]]
    ) -> tuple[list[dict[str, Any]], list[str]]:
        values, refused = self.bridge._params.set(parameters)
        for text in refused:
            logger.warning("foxglove: %s", text)
        return values, refused
