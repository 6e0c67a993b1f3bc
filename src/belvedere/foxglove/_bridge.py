"""The bridge: topics become channels, a client's subscription becomes the graph's.

Three threads meet here. The SDK calls the listener (a client subscribes, publishes, asks
for parameters) on threads of its own; the graph delivers messages on its executor thread;
the bridge's own thread turns them into ROS 1 bytes, hands them to the SDK and keeps the
channel list in step with the graph. The executor only appends to a queue, so a simulation
is not slowed by serialization for Foxglove.
"""

from __future__ import annotations

import logging
import re
import threading
import time
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache, partial
from types import ModuleType
from typing import TYPE_CHECKING, Any, Final

from belvedere.errors import BelvedereError
from belvedere.foxglove._inbound import ClientPublishing, Parameters
from belvedere.graph import Graph, GraphError, GraphTopics, Node, Subscription
from belvedere.msgs import MessageTypeError, types

if TYPE_CHECKING:
    from foxglove.websocket import ChannelView, Client, ClientChannel, WebSocketServer

    import foxglove

__all__ = [
    "DEFAULT_PORT",
    "MESSAGE_ENCODING",
    "SCHEMA_ENCODING",
    "FoxgloveBridge",
    "FoxgloveBridgeError",
    "require_sdk",
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


class FoxgloveBridgeError(BelvedereError):
    """The bridge cannot start as asked (no SDK, the port taken)."""


def require_sdk() -> ModuleType:
    """The ``foxglove`` package, or one error saying how to install it."""
    try:
        import foxglove.websocket

        import foxglove
    except ImportError as err:
        msg = f"the Foxglove bridge needs the foxglove-sdk package, which is not installed ({err})"
        raise FoxgloveBridgeError(
            msg, hint="pip install 'belvedere[foxglove]' (or: pip install foxglove-sdk)"
        ) from None
    return foxglove


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
    channel: foxglove.Channel
    id: int
    clients: set[int] = field(default_factory=set)
    """Clients subscribed to it."""
    subscription: Subscription | None = None
    """The graph's subscription (executor thread), while a client is subscribed."""
    closed: bool = False


class FoxgloveBridge:
    """Serves ``graph``'s topics to Foxglove clients on ``host:port`` (0: any free port).

    ``node_name``: the bridge's node on the graph. Stop with :meth:`close`.
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
    ) -> None:
        """``node``: the bridge's node, when one exists already (a launch file's); else one
        named ``node_name`` is made. ``topic_whitelist``: regular expressions, one of which
        must match a topic's whole name for it to be served (foxglove_bridge's parameter)."""
        fox = require_sdk()
        from foxglove.websocket import Capability

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
        self._wake = threading.Event()
        self._dirty = threading.Event()
        self._stop = threading.Event()
        self._context = fox.Context()
        self._publishing = ClientPublishing(self.node)
        self._params = Parameters(graph)
        try:
            self.server: WebSocketServer = fox.start_server(
                name="belvedere",
                host=host,
                port=port,
                context=self._context,
                server_listener=_Listener(self),
                capabilities=[Capability.Time, Capability.ClientPublish, Capability.Parameters],
                supported_encodings=list(ClientPublishing.ENCODINGS),
            )
        except RuntimeError as err:
            reason = str(err).removeprefix("FoxgloveError: ")
            msg = f"cannot serve Foxglove on {host}:{port}: {reason}"
            self._leave()
            raise FoxgloveBridgeError(
                msg, hint="choose another port: --foxglove PORT (0: any free one)"
            ) from None
        self._publishing.status = self.server.publish_status
        self.host = host
        self.port = self.server.port
        self._topics = GraphTopics(graph, on_change=self._publishers_changed)
        self._refresh()
        self._thread = threading.Thread(target=self._run, name="belvedere-foxglove", daemon=True)
        self._thread.start()

    @property
    def url(self) -> str:
        """``ws://host:port``: what Foxglove's "Open connection" asks for."""
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"ws://{host}:{self.port}"

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
            ch.channel.close()
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
        import foxglove

        try:
            name, text = ros1_schema(msgtype)
        except BelvedereError as err:
            self._skip(topic, msgtype, err.message)
            return
        schema = foxglove.Schema(name=name, encoding=SCHEMA_ENCODING, data=text.encode())
        channel = foxglove.Channel(
            topic, schema=schema, message_encoding=MESSAGE_ENCODING, context=self._context
        )
        ch = _Channel(topic, msgtype, channel, channel.id())
        with self._lock:
            self._channels[topic] = ch
            self._by_id[ch.id] = ch
        logger.debug("foxglove: advertised %s [%s]", topic, name)

    def _withdraw(self, ch: _Channel) -> None:
        ch.closed = True
        ch.clients.clear()
        ch.channel.close()
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
        except GraphError as err:
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
            except Exception:  # the bridge keeps serving; the cause is in the log
                logger.exception("foxglove: bridge error")

    def _send(self) -> None:
        serialize = types().store.serialize_ros1
        outbox = self._outbox
        while outbox:
            try:
                ch, stamp, msg = outbox.popleft()
            except IndexError:
                break
            if ch.closed:
                continue
            ch.channel.log(bytes(serialize(msg, ch.msgtype)), log_time=stamp)
            self.sent += 1


class _Listener:
    """The SDK's callbacks (its threads), passed on."""

    def __init__(self, bridge: FoxgloveBridge) -> None:
        self.bridge = bridge

    def on_subscribe(self, client: Client, channel: ChannelView) -> None:
        self.bridge.subscribed(client.id, channel.id)

    def on_unsubscribe(self, client: Client, channel: ChannelView) -> None:
        self.bridge.unsubscribed(client.id, channel.id)

    def on_client_advertise(self, client: Client, channel: ClientChannel) -> None:
        self.bridge._publishing.advertise(
            client.id, channel.id, channel.topic, channel.encoding, channel.schema_name
        )

    def on_client_unadvertise(self, client: Client, client_channel_id: int) -> None:
        self.bridge._publishing.unadvertise(client.id, client_channel_id)

    def on_message_data(self, client: Client, client_channel_id: int, data: bytes) -> None:
        self.bridge._publishing.message(client.id, client_channel_id, data)

    def on_get_parameters(
        self, client: Client, param_names: list[str], request_id: str | None = None
    ) -> list[foxglove.Parameter]:
        return self.bridge._params.get(param_names)

    def on_set_parameters(
        self, client: Client, parameters: list[foxglove.Parameter], request_id: str | None = None
    ) -> list[foxglove.Parameter]:
        return self.bridge._params.set(parameters)
