"""The Zenoh transport: topics, latched topics, services, parameters and introspection
across processes, CDR-encoded as ROS 2 sends them.

Graphs have an identity, as ``ROS_DOMAIN_ID`` gives ROS 2's: a domain number ``d`` from 0 to
232 (``BELVEDERE_DOMAIN``, ``--domain``; default 0). Domain ``d`` meets on the endpoint
``tcp/127.0.0.1:<7450 + d>`` (7450 … 7682: TCP, below the ephemeral range, clear of Zenoh's
own 7447; ROS 2's DDS uses UDP) and keeps every key under ``bv/<d>/``, so two domains stay
apart even when ``BELVEDERE_ENDPOINT``/``--endpoint`` points them at one endpoint.

Default: localhost only, no scouting. The first process of a domain listens on its endpoint;
later ones connect to it. Opening to other machines is explicit (``listen_on`` another
address). Messages are serialized only when a subscriber in another process wants them.
Publications use BLOCK congestion control, so commands are never silently dropped.

Queue size 1 or 2 means "the newest" for bulky data: images, point clouds and maps (a ``data``
array of 64 KiB or more) whose publishers all have such a queue go through an outbox that
keeps only the newest ``queue_size`` messages and is sent from a thread of its own, so a slow
link or subscriber drops old frames instead of slowing the simulation (as ROS 1's publisher
queue does). Everything else (commands, odometry, TF) is sent at once and never lost.
On the receiving side, a topic whose subscriptions all have queue size 1 or 2 keeps only
that many undelivered samples and deserializes only those: a subscriber with queue size 1
always gets the newest message, never a backlog. Other topics deliver every sample.

Key expressions (under ``bv/<d>``): ``t/<topic>`` data; ``l/<topic>`` each latching
publisher's last message; ``s/<service>`` service calls; ``p`` parameters; liveliness tokens
under ``g/…`` say which node publishes, subscribes or serves what, with which type, and which
process (pid, host) holds each node since when. A node whose name another process takes
later is shut down, as ROS 1's master does ("new node registered with same name").
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import socket
import struct
import threading
import time
import weakref
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any, Final, cast

import zenoh

from belvedere.errors import BelvedereError
from belvedere.graph._endpoints import Publisher, ServiceServer, Subscription, Topic
from belvedere.graph._errors import GraphError, ServiceFailedError, ServiceUnavailableError
from belvedere.graph._graph import Graph, Node
from belvedere.msgs import short, types

__all__ = [
    "DEFAULT_ENDPOINT",
    "MAX_DOMAIN",
    "GraphInfo",
    "LatchedOnce",
    "Sent",
    "TransportError",
    "ZenohTransport",
    "check_domain",
    "decode_key",
    "domain_endpoint",
    "encode_key",
]

logger = logging.getLogger("belvedere.transport")

BASE_PORT: Final = 7450
"""Domain ``d`` listens on ``BASE_PORT + d``."""
MAX_DOMAIN: Final = 232
"""The highest domain (as ROS 2's ``ROS_DOMAIN_ID``)."""
DEFAULT_ENDPOINT: Final = f"tcp/127.0.0.1:{BASE_PORT}"
"""Domain 0's endpoint."""
_STAMP: Final = struct.Struct("<cq")
"""A message's publication time, sent with it: kind (``s`` simulated, ``w`` wall) and ns.
After it come the message's type and its publisher's node (``type\nnode``): a subscriber
that wants another type drops the message unread and says so once (ROS 1 refuses such a
connection when it is made; Zenoh has no connections)."""
NEWEST_ONLY: Final = 2
"""Publishers with a queue size up to this (and above 0) want only their newest messages sent."""


@dataclass(slots=True)
class TopicStats:
    """What the transport did with one topic's messages (for benchmarks and ``topic hz``)."""

    sent: int = 0
    """Messages handed to Zenoh."""
    superseded: int = 0
    """Messages not sent because newer ones came before the link was free."""
    serialize_s: float = 0.0
    """Time spent serializing sent messages."""
    put_s: float = 0.0
    """Time spent handing them to Zenoh (blocked while the link is congested)."""
    received: int = 0
    """Samples that arrived from other processes."""
    skipped: int = 0
    """Samples dropped unread because newer ones arrived before the subscribers were ready."""


BULKY: Final = 64 * 1024
"""Bytes of a message's ``data`` array from which sending it takes long enough to matter."""


@dataclass(frozen=True, slots=True)
class Sent:
    """What a message carries besides its bytes (a Zenoh attachment)."""

    stamp: tuple[bool, int] | None = None
    """(simulated?, ns): the publishing graph's time when it was published."""
    type: str | None = None
    node: str | None = None
    """The publisher's node."""
    latch: tuple[str, int] | None = None
    """A latching publisher's message: (that publisher, the number of its publication). The
    same publication can come again: see :class:`LatchedOnce`."""


def _sender(text: str) -> tuple[str | None, str | None, tuple[str, int] | None]:
    """``type\nnode[\npublisher:number]``: what follows a message's stamp, and what a latched
    reply carries."""
    type_name, _, rest = text.partition("\n")
    node, _, tag = rest.partition("\n")
    who, _, number = tag.rpartition(":")
    latch = (who, int(number)) if who and number.isdigit() else None
    return type_name or None, node or None, latch


def _sent(attachment: Any) -> Sent:
    if attachment is None:
        return Sent()
    raw = attachment.to_bytes()
    if len(raw) < _STAMP.size:
        return Sent()
    kind, ns = _STAMP.unpack_from(raw)
    return Sent((kind == b"s", ns), *_sender(raw[_STAMP.size :].decode(errors="replace")))


class LatchedOnce:
    """The latched publications one receiver has had, so that it takes each exactly once
    however it came: published while it listened, replied to its question for latched
    messages, or sent again when its publisher first saw a subscriber elsewhere (as ROS 1
    sends the latched message on every new connection)."""

    def __init__(self) -> None:
        self._newest: dict[str, int] = {}
        """Each latching publisher's newest publication had."""

    def fresh(self, latch: tuple[str, int] | None) -> bool:
        """Whether a message (``latch``: see :attr:`Sent.latch`) is new to this receiver."""
        if latch is None:
            return True
        who, number = latch
        if self._newest.get(who, -1) >= number:
            return False
        self._newest[who] = number
        return True


class _LatchedSeen:
    """A :class:`LatchedOnce` for each subscription. Used on the executor's thread only."""

    def __init__(self) -> None:
        self._seen: weakref.WeakKeyDictionary[Subscription, LatchedOnce] = (
            weakref.WeakKeyDictionary()
        )

    def fresh(self, subscription: Subscription, latch: tuple[str, int] | None) -> bool:
        once = self._seen.get(subscription)
        if once is None:
            once = self._seen[subscription] = LatchedOnce()
        return once.fresh(latch)


def _prepare(type_name: str) -> None:
    types().prepare(type_name)


def _bulky(msg: Any) -> bool:
    """An image, point cloud or map: a ``data`` array of :data:`BULKY` bytes or more."""
    data = getattr(msg, "data", None)
    return int(getattr(data, "nbytes", 0)) >= BULKY


class _Outbox:
    """The newest messages of queue-size-1/2 topics, sent from a thread of their own."""

    def __init__(
        self, put: Callable[[Topic, Any, bytes], None], stats: Callable[[str], TopicStats]
    ):
        self._put = put
        self._stats = stats
        self._queues: dict[str, tuple[Topic, deque[Any]]] = {}
        self._ready: deque[str] = deque()
        self._busy = False
        self._cond = threading.Condition()
        self._closed = False
        self._thread: threading.Thread | None = None

    def push(self, topic: Topic, msg: Any, stamp: bytes, depth: int) -> None:
        with self._cond:
            if self._closed:
                return
            entry = self._queues.get(topic.name)
            if entry is None or entry[1].maxlen != depth:
                old = entry[1] if entry is not None else ()
                entry = self._queues[topic.name] = (topic, deque(old, maxlen=depth))
            queue = entry[1]
            if len(queue) == depth:
                self._stats(topic.name).superseded += 1
            queue.append((msg, stamp))
            if topic.name not in self._ready:
                self._ready.append(topic.name)
            if self._thread is None:
                self._thread = threading.Thread(
                    target=self._run, name="belvedere-outbox", daemon=True
                )
                self._thread.start()
            self._cond.notify()

    def _run(self) -> None:
        while True:
            with self._cond:
                self._busy = False
                self._cond.notify_all()
                while not self._ready and not self._closed:
                    self._cond.wait()
                if not self._ready:
                    return
                name = self._ready.popleft()
                topic, queue = self._queues[name]
                msg, stamp = queue.popleft()
                if queue:
                    self._ready.append(name)
                self._busy = True
            try:
                self._put(topic, msg, stamp)
            except Exception as err:  # noqa: BLE001 (a closed session, a refused message)
                logger.debug("not sent on %s: %s", topic.name, err)

    def flush(self, timeout: float) -> bool:
        """Wait until everything queued is sent (True), or ``timeout`` seconds."""
        with self._cond:
            return self._cond.wait_for(lambda: not self._ready and not self._busy, timeout)

    def close(self, timeout: float = 2.0) -> None:
        self.flush(timeout)
        with self._cond:
            self._closed = True
            self._cond.notify_all()


class TransportError(BelvedereError):
    """The transport could not start, or a remote call failed."""


def check_domain(value: int | str | None = None) -> int:
    """The graph domain: ``value``, else ``BELVEDERE_DOMAIN``, else 0 — a whole number from
    0 to :data:`MAX_DOMAIN`."""
    where = "domain"
    if value is None:
        value = os.environ.get("BELVEDERE_DOMAIN", "").strip() or 0
        where = "BELVEDERE_DOMAIN"
    try:
        domain = int(value)
    except ValueError:
        domain = -1
    if not 0 <= domain <= MAX_DOMAIN:
        msg = f"{where} {value!r} is not a graph domain (a whole number from 0 to {MAX_DOMAIN})"
        raise TransportError(msg)
    return domain


def domain_endpoint(domain: int) -> str:
    """Where domain ``domain`` meets: ``tcp/127.0.0.1:<7450 + domain>``."""
    return f"tcp/127.0.0.1:{BASE_PORT + domain}"


def encode_key(name: str) -> str:
    """One key-expression chunk for a graph name or type (``/a/b`` → ``%a%b``)."""
    return name.replace("/", "%") or "%"


def decode_key(chunk: str) -> str:
    return chunk.replace("%", "/")


def graph_running(endpoint: str | None = None, domain: int | None = None) -> bool:
    """Is a graph already listening on the endpoint (``--endpoint``/``--domain``'s, else the
    environment's)? Only TCP endpoints can be asked; others count as not running."""
    endpoint = (
        endpoint or os.environ.get("BELVEDERE_ENDPOINT") or domain_endpoint(check_domain(domain))
    )
    proto, _, where = endpoint.partition("/")
    host, _, port = where.rpartition(":")
    if proto != "tcp" or not port.isdigit():
        return False
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=0.5):
            return True
    except OSError:
        return False


def _config(mode: str, *, listen: str | None, connect: str | None) -> zenoh.Config:
    conf = zenoh.Config()
    conf.insert_json5("mode", json.dumps(mode))
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("scouting/gossip/enabled", "false")
    conf.insert_json5("listen/endpoints", json.dumps([listen] if listen else []))
    conf.insert_json5("connect/endpoints", json.dumps([connect] if connect else []))
    return conf


def open_session(endpoint: str | None = None, *, role: str = "auto") -> tuple[zenoh.Session, str]:
    """Open a session: listen on the endpoint if it is free (``auto``/``listen``), else
    connect to whoever listens there (``auto``/``connect``). Returns (session, role taken)."""
    endpoint = endpoint or os.environ.get("BELVEDERE_ENDPOINT") or domain_endpoint(check_domain())
    errors = []
    if role in ("auto", "listen"):
        try:
            return zenoh.open(_config("peer", listen=endpoint, connect=None)), "listen"
        except zenoh.ZError as err:
            errors.append(str(err).split(" at ")[0])
    if role in ("auto", "connect"):
        try:
            return zenoh.open(_config("client", listen=None, connect=endpoint)), "connect"
        except zenoh.ZError as err:
            errors.append(str(err).split(" at ")[0])
    msg = f"cannot open the transport on {endpoint}: {'; '.join(errors)}"
    raise TransportError(
        msg, hint="use another domain (--domain N), or --endpoint with a free port"
    )


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


def _close_at_exit(ref: weakref.ref[ZenohTransport]) -> None:
    transport = ref()
    if transport is not None:
        transport.close()


class ZenohTransport:
    """Carries a graph's traffic to and from other processes."""

    def __init__(
        self,
        *,
        endpoint: str | None = None,
        domain: int | None = None,
        role: str = "auto",
        serve_params: bool = True,
    ) -> None:
        """``domain`` (default ``BELVEDERE_DOMAIN`` or 0) picks the endpoint and the key
        prefix; ``endpoint`` (default ``BELVEDERE_ENDPOINT``) overrides the endpoint only."""
        self.domain = check_domain(domain)
        self.endpoint = (
            endpoint or os.environ.get("BELVEDERE_ENDPOINT") or domain_endpoint(self.domain)
        )
        self.session, self.role = open_session(self.endpoint, role=role)
        self.prefix = f"bv/{self.domain}"
        self.serve_params = serve_params
        self.graph: Graph | None = None
        self._zid = str(self.session.zid())
        self._process = f"pid {os.getpid()} on {socket.gethostname()}"
        self._publishers: dict[str, Any] = {}
        self._matching: dict[str, Any] = {}
        self._subscribers: dict[str, Any] = {}
        self._latch_queryables: dict[str, Any] = {}
        self._latched_seen = _LatchedSeen()
        self._latched_sent: weakref.WeakKeyDictionary[Publisher, int] = weakref.WeakKeyDictionary()
        """The number of each latching publisher's last message handed to Zenoh."""
        self._service_queryables: dict[str, Any] = {}
        self._tokens: dict[tuple[str, ...], Any] = {}
        self._param_queryable: Any = None
        self._node_watch: Any = None
        self._own_nodes: dict[str, tuple[int, Node]] = {}
        """full name → (when taken, node)"""
        self._clashes: set[tuple[str, str]] = set()
        """(node name, other process's zid) already settled"""
        self._mismatches: set[tuple[str, str, str]] = set()
        """(topic, type, node) of publishers of another type already warned about"""
        self._lock = threading.Lock()
        self._closed = False
        self.stats: dict[str, TopicStats] = {}
        """Per topic: what was sent and received, and what newer messages superseded."""
        self._outbox = _Outbox(self._put, self._topic_stats)
        # Zenoh runs callbacks on a non-daemon thread: a process that never closes its
        # session would wait for it forever at exit. Close it first (threading's own hook
        # runs before that wait; atexit runs after it).
        threading._register_atexit(partial(_close_at_exit, weakref.ref(self)))  # type: ignore[attr-defined]

    def _key(self, kind: str, name: str = "") -> str:
        """``bv/<domain>/<kind><name>`` (graph names start with '/')."""
        return f"{self.prefix}/{kind}{name}"

    # --- lifecycle -----------------------------------------------------------------------------
    def attach(self, graph: Graph) -> None:
        self.graph = graph
        if self.serve_params:
            self._param_queryable = self.session.declare_queryable(
                self._key("p"), self._on_param_query
            )
        # New holders of node names from now on (no history: those before are asked for when
        # a node is added; with history, zenoh 1.x answers a liveliness query made right after
        # with nothing).
        self._node_watch = self.session.liveliness().declare_subscriber(
            self._key("g/node/**"), self._on_node_token
        )

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        self._outbox.close()
        with contextlib.suppress(zenoh.ZError):
            self.session.close()  # type: ignore[no-untyped-call]

    def _token(self, *parts: str, extra: tuple[str, ...] = ()) -> None:
        key = tuple(parts)
        if key not in self._tokens:
            chunks = [encode_key(p) for p in parts]
            expr = "/".join([self._key("g"), *chunks, self._zid, *extra])
            self._tokens[key] = self.session.liveliness().declare_token(expr)

    def _drop_token(self, *parts: str) -> None:
        token = self._tokens.pop(tuple(parts), None)
        if token is not None:
            token.undeclare()

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

    # --- topics --------------------------------------------------------------------------------
    def advertise(self, topic: Topic, publisher: Publisher) -> None:
        # The token goes last: whoever sees it finds the publisher and its latched messages.
        self._declare_publisher(topic, publisher)
        self._token("pub", topic.name, topic.type, publisher.node.full_name)

    def _declare_publisher(self, topic: Topic, publisher: Publisher) -> None:
        with self._lock:
            if topic.name not in self._publishers:
                zpub = self.session.declare_publisher(
                    self._key("t", topic.name),
                    congestion_control=zenoh.CongestionControl.BLOCK,
                    allowed_destination=zenoh.Locality.REMOTE,
                )
                self._publishers[topic.name] = zpub

                def matching(status: Any) -> None:
                    first = bool(status.matching) and not topic.remote
                    topic.remote = bool(status.matching)
                    graph = self.graph
                    if first and graph is not None:
                        # The first message to go out is then sent at once: the serializer
                        # is made now, in the executor's time between callbacks.
                        graph.executor.post(partial(_prepare, topic.type))
                    if first and topic.latched and graph is not None:
                        # A subscriber elsewhere that was there before this publisher (its
                        # query at subscribing found nothing) gets the latched messages now;
                        # ones published before Zenoh saw it went nowhere.
                        graph.executor.post(partial(self._send_latched, topic))

                self._matching[topic.name] = zpub.declare_matching_listener(matching)
                # (zenoh's type stubs call this a bool; it is a MatchingStatus)
                topic.remote = bool(cast(Any, zpub).matching_status.matching)
        if publisher.latch and topic.name not in self._latch_queryables:
            graph = self.graph
            if graph is not None:
                # Asked for as soon as a subscriber elsewhere appears: ready to answer at
                # once (made between callbacks, not in the one advertising: a node's first
                # log line waits for no /rosout serializer).
                graph.executor.post(partial(_prepare, topic.type))

            def latched(query: Any) -> None:
                for pub in list(topic.latched):
                    number, msg = pub.latched
                    query.reply(
                        self._key("l", topic.name),
                        types().serialize(msg),
                        attachment=self._sender(pub, number).encode(),
                    )

            self._latch_queryables[topic.name] = self.session.declare_queryable(
                self._key("l", topic.name), latched
            )

    def unadvertise(self, topic: Topic, publisher: Publisher) -> None:
        self._drop_token("pub", topic.name, topic.type, publisher.node.full_name)

    def _topic_stats(self, name: str) -> TopicStats:
        stats = self.stats.get(name)
        if stats is None:
            stats = self.stats[name] = TopicStats()
        return stats

    def send(self, topic: Topic, msg: Any, publisher: Publisher) -> None:
        stamp = self._stamp(publisher)
        if publisher.latch:
            self._latched_sent[publisher] = publisher.count
        depth = max((p.queue_size for p in topic.publishers), default=0)
        if (
            0 < depth <= NEWEST_ONLY
            and min(p.queue_size for p in topic.publishers) > 0
            and _bulky(msg)
        ):
            self._outbox.push(topic, msg, stamp, depth)
        else:
            self._put(topic, msg, stamp)

    def _send_latched(self, topic: Topic) -> None:
        """Send the latched messages that were published while nobody elsewhere listened (the
        ones sent then reached every subscriber there was; later ones ask for them)."""
        for pub in list(topic.latched):
            number, msg = pub.latched
            if self._latched_sent.get(pub) != number:
                self._latched_sent[pub] = number
                self._put(topic, msg, self._stamp(pub, number))

    def _sender(self, publisher: Publisher, number: int) -> str:
        """What a message says of its sender: its type and node, and for a latching
        publisher, which one it is and the number of this publication."""
        text = f"{publisher.topic.type}\n{publisher.node.full_name}"
        if publisher.latch:
            text += f"\n{self._zid}.{id(publisher):x}:{number}"
        return text

    def _stamp(self, publisher: Publisher, number: int | None = None) -> bytes:
        """When a message is published, in the publishing graph's time: ``s`` (simulated)
        or ``w`` (wall) and nanoseconds, then its type and node. Sent with each message (a
        Zenoh attachment), so a recorder in another process stamps it exactly, whatever order
        its topics arrive in, and a subscriber of another type knows whom to name."""
        graph = self.graph
        if graph is None:
            return b""
        sender = self._sender(publisher, publisher.count if number is None else number)
        return _STAMP.pack(b"s" if graph.sim_time else b"w", graph.now_ns()) + sender.encode()

    def flush(self, timeout: float = 5.0) -> bool:
        """Wait until the newest-only topics' messages are handed to Zenoh."""
        return self._outbox.flush(timeout)

    def _put(self, topic: Topic, msg: Any, stamp: bytes) -> None:
        zpub = self._publishers.get(topic.name)
        if zpub is None:
            return
        start = time.perf_counter()
        data = types().serialize(msg)
        serialized = time.perf_counter()
        zpub.put(data, attachment=stamp or None)
        stats = self._topic_stats(topic.name)
        stats.sent += 1
        stats.serialize_s += serialized - start
        stats.put_s += time.perf_counter() - serialized

    def subscribe(self, topic: Topic, subscription: Subscription) -> None:
        self._token("sub", topic.name, topic.type, subscription.node.full_name)
        graph = self.graph
        assert graph is not None
        # Each new subscription gets the last latched messages of other processes, also when
        # the topic has subscribers here already (rospy gives every new subscriber those);
        # asked for once Zenoh delivers the topic's samples here, so none falls in between.
        if topic.name not in self._subscribers:
            # Ready to read the first message before anyone can send it (not when it comes).
            types().prepare(topic.type)
        with self._lock:
            if topic.name in self._subscribers:
                self._ask_latched(topic, subscription)
                return

            seen = self._latched_seen

            def deliver(msg: Any, latch: tuple[str, int] | None) -> None:
                for sub in list(topic.subscriptions):
                    if seen.fresh(sub, latch):
                        sub.enqueue(msg)

            # Samples arrive on Zenoh's thread: queue their bytes and wake the executor once
            # per burst, not once per message.
            arrived: deque[tuple[bytes, tuple[str, int] | None]] = deque()
            scheduled = [False]

            def flush() -> None:
                scheduled[0] = False
                while arrived:
                    try:
                        data, latch = arrived.popleft()
                    except IndexError:  # the newest-only trim took it meanwhile
                        break
                    try:
                        msg = types().deserialize(data, topic.type)
                    except Exception as err:  # noqa: BLE001 (a peer sent something else)
                        self._mismatch(topic, None, None, str(err))
                        continue
                    deliver(msg, latch)
                    graph.executor.run_ready()  # each message's callbacks run before the next

            stats = self._topic_stats(topic.name)

            def on_sample(sample: Any) -> None:
                sent = _sent(sample.attachment)
                if sent.type is not None and sent.type != topic.type:
                    self._mismatch(topic, sent.type, sent.node)
                    return
                arrived.append((sample.payload.to_bytes(), sent.latch))
                stats.received += 1
                # Subscriptions that all want only the newest (queue size 1 or 2) keep
                # that many samples; others keep every one (as before a burst is delivered).
                depths = [sub.pending.maxlen or 0 for sub in topic.subscriptions]
                keep = max(depths, default=0)
                if min(depths, default=0) > 0 and keep <= NEWEST_ONLY:
                    while len(arrived) > keep:
                        try:
                            arrived.popleft()
                        except IndexError:  # the executor took it meanwhile
                            break
                        stats.skipped += 1
                if not scheduled[0]:
                    scheduled[0] = True
                    graph.executor.post(flush)

            self._subscribers[topic.name] = self.session.declare_subscriber(
                self._key("t", topic.name), on_sample, allowed_origin=zenoh.Locality.REMOTE
            )
        self._ask_latched(topic, subscription)

    def _ask_latched(self, topic: Topic, subscription: Subscription) -> None:
        """Ask the latching publishers elsewhere for their last messages; each reply goes to
        ``subscription`` as it comes (on Zenoh's thread: no thread to start, no wait for the
        other replies), read on the executor's as samples are."""
        graph = self.graph
        assert graph is not None

        def on_reply(reply: Any) -> None:
            if reply.ok is None:
                return
            attachment = reply.ok.attachment
            sent_type, node, latch = _sender(
                attachment.to_bytes().decode(errors="replace") if attachment is not None else ""
            )
            if sent_type and sent_type != topic.type:
                self._mismatch(topic, sent_type, node)
                return
            data = reply.ok.payload.to_bytes()
            graph.executor.post(partial(self._deliver_latched, topic, subscription, data, latch))

        with contextlib.suppress(zenoh.ZError):
            # Every latching publisher replies under the same key: keep them all. This
            # process's own latched messages are delivered by the graph already.
            self.session.get(
                self._key("l", topic.name),
                on_reply,
                timeout=2.0,
                consolidation=zenoh.ConsolidationMode.NONE,
                allowed_destination=zenoh.Locality.REMOTE,  # ours came when it subscribed
            )

    def _deliver_latched(
        self, topic: Topic, subscription: Subscription, data: bytes, latch: tuple[str, int] | None
    ) -> None:
        if not self._latched_seen.fresh(subscription, latch):
            return
        try:
            msg = types().deserialize(data, topic.type)
        except Exception as err:  # noqa: BLE001 (a peer sent something else)
            self._mismatch(topic, None, None, str(err))
            return
        subscription.enqueue(msg)

    def _mismatch(
        self, topic: Topic, sent_type: str | None, node: str | None, why: str = ""
    ) -> None:
        """Say once per publisher (and type) that its messages on ``topic`` are dropped: they
        are not of the type subscribers here want (in rospy's words for such a connection)."""
        key = (topic.name, sent_type or "", node or "")
        with self._lock:
            if key in self._mismatches:
                return
            self._mismatches.add(key)
        if sent_type is None:
            logger.warning(
                "dropping messages on %s that are not %s: %s", topic.name, short(topic.type), why
            )
            return
        logger.warning(
            "topic types do not match on %s: [%s] here vs. [%s] from %s; its messages are dropped",
            topic.name,
            short(topic.type),
            short(sent_type),
            node or "another process",
        )

    def unsubscribe(self, topic: Topic, subscription: Subscription) -> None:
        self._drop_token("sub", topic.name, topic.type, subscription.node.full_name)
        if topic.subscriptions:
            return
        # The last subscription here is gone: so is Zenoh's, and publishers elsewhere stop
        # sending this process what nobody here reads (a viewer or bridge whose last client
        # left, a display removed).
        with self._lock:
            zsub = self._subscribers.pop(topic.name, None)
        if zsub is not None:
            zsub.undeclare()

    # --- raw access (recorders) ----------------------------------------------------------------
    def tap(self, topic: str | None, callback: Callable[[str, bytes, Sent], None]) -> Any:
        """Call ``callback(topic, cdr_bytes, sent)`` on Zenoh's thread for each message other
        processes publish on ``topic`` (on every topic when None), never deserialized here.
        One tap delivers in arrival order; separate taps run on separate threads. Returns the
        subscriber (``undeclare()`` ends it). A tap on every topic makes every publisher send
        (as ``rosbag record -a`` subscribes to all)."""
        prefix = self._key("t")
        key = self._key("t", topic) if topic else self._key("t/**")
        skip = len(prefix)

        def on_sample(sample: Any) -> None:
            sent = _sent(sample.attachment)
            callback(str(sample.key_expr)[skip:], sample.payload.to_bytes(), sent)

        return self.session.declare_subscriber(key, on_sample)

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

    def latched_raw(self, topic: str, timeout: float = 2.0) -> list[tuple[bytes, Sent]]:
        """The messages latching publishers in other processes hold on ``topic`` (none if no
        publisher there latches): their CDR bytes and what they say of their sender (no
        stamp)."""
        found: list[tuple[bytes, Sent]] = []
        with contextlib.suppress(zenoh.ZError):
            replies = self.session.get(
                self._key("l", topic),
                timeout=timeout,
                consolidation=zenoh.ConsolidationMode.NONE,
                allowed_destination=zenoh.Locality.REMOTE,
            )
            for reply in replies:
                if reply.ok is None:
                    continue
                attachment = reply.ok.attachment
                text = attachment.to_bytes().decode(errors="replace") if attachment else ""
                found.append((reply.ok.payload.to_bytes(), Sent(None, *_sender(text))))
        return found

    # --- services ------------------------------------------------------------------------------
    def offer_service(self, server: ServiceServer) -> None:
        self._token("srv", server.name, server.type, server.node.full_name)
        graph = self.graph
        assert graph is not None

        def on_query(query: Any) -> None:
            done = threading.Event()
            result: list[Any] = []

            def run() -> None:
                try:
                    request = types().deserialize(
                        query.payload.to_bytes(), f"{server.type}_Request"
                    )
                    result.append(types().serialize(server.handle(request)))
                except Exception as err:  # noqa: BLE001 (the caller gets the error)
                    result.append(err)
                finally:
                    done.set()

            if server.threaded:
                threading.Thread(target=run, name=f"service {server.name}", daemon=True).start()
            else:
                graph.executor.post(run)
            limit = 3600.0 if server.threaded else 30.0  # rospy's handlers may take long
            if not done.wait(limit):
                query.reply_err(f"service handler did not answer within {limit:g} s".encode())
                return
            outcome = result[0]
            if isinstance(outcome, ServiceFailedError):
                query.reply_err(outcome.reason.encode())
            elif isinstance(outcome, Exception):
                query.reply_err(str(outcome).encode())
            else:
                query.reply(self._key("s", server.name), result[0])

        self._service_queryables[server.name] = self.session.declare_queryable(
            self._key("s", server.name), on_query
        )

    def withdraw_service(self, server: ServiceServer) -> None:
        self._drop_token("srv", server.name, server.type, server.node.full_name)
        queryable = self._service_queryables.pop(server.name, None)
        if queryable is not None:
            queryable.undeclare()

    def call_service(self, name: str, srv_type: str, request: Any, timeout: float) -> Any:
        replies = self.session.get(
            self._key("s", name),
            payload=types().serialize(request),
            timeout=timeout,
            target=zenoh.QueryTarget.BEST_MATCHING,
        )
        for reply in replies:
            if reply.ok is not None:
                return types().deserialize(reply.ok.payload.to_bytes(), f"{srv_type}_Response")
            if reply.err is not None:
                why = reply.err.payload.to_bytes().decode(errors="replace")
                raise ServiceFailedError(name, why)
        msg = f"service {name} is not offered by any node (waited {timeout:g} s)"
        raise ServiceUnavailableError(msg, hint="is the node that provides it running?")

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

    # --- parameters ----------------------------------------------------------------------------
    def _on_param_query(self, query: Any) -> None:
        graph = self.graph
        assert graph is not None
        try:
            request = json.loads(query.payload.to_bytes())
            op, name = request["op"], request.get("name", "/")
            params = graph.params
            if op == "get":
                value: Any = params.get(name)
            elif op == "set":
                params.set(name, request["value"])
                value = None
            elif op == "delete":
                params.delete(name)
                value = None
            elif op == "has":
                value = params.has(name)
            elif op == "list":
                value = params.names(name)
            elif op == "load":
                params.load_yaml(request["yaml"], name, source=request.get("source", "<yaml>"))
                value = None
            elif op == "dump":
                value = params.dump_yaml(name)
            else:
                msg = f"unknown parameter operation {op!r}"
                raise TransportError(msg)
            reply = {"ok": True, "value": value}
        except BelvedereError as err:
            reply = {"ok": False, "error": err.message}
        except (KeyError, ValueError, TypeError) as err:
            reply = {"ok": False, "error": f"bad parameter request: {err}"}
        query.reply(self._key("p"), json.dumps(reply).encode())

    def param_request(self, request: dict[str, Any], timeout: float = 2.0) -> Any:
        """Ask the graph that holds the parameters (another process)."""
        replies = self.session.get(
            self._key("p"), payload=json.dumps(request).encode(), timeout=timeout
        )
        for reply in replies:
            if reply.ok is None:
                continue
            answer = json.loads(reply.ok.payload.to_bytes())
            if not answer["ok"]:
                raise GraphError(answer["error"])
            return answer["value"]
        msg = "no running graph holds parameters (start a simulation or launch file first)"
        raise GraphError(msg)

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
