"""The Zenoh transport: topics, latched topics, services, parameters and introspection
across processes, CDR-encoded as ROS 2 sends them.

This module is the transport itself (:class:`ZenohTransport`) and its traffic: topics and
services. Its other parts: domains, sessions and the key layout (``_zenoh_session``); who is
on the graph (``_zenoh_discovery``); what a message carries and latching (``_zenoh_latch``);
the newest-only outbox (``_zenoh_outbox``); the parameter service (``_zenoh_params``); the
definitions of types other processes do not know (``_zenoh_types``).

Messages are serialized only when a subscriber in another process wants them. Publications
use BLOCK congestion control, so commands are never silently dropped.

Queue size 1 or 2 means "the newest" for bulky data: images, point clouds and maps (a ``data``
array of 64 KiB or more) whose publishers all have such a queue go through an outbox that
keeps only the newest ``queue_size`` messages and is sent from a thread of its own, so a slow
link or subscriber drops old frames instead of slowing the simulation (as ROS 1's publisher
queue does). Everything else (commands, odometry, TF) is sent at once and never lost.
On the receiving side, a topic whose subscriptions all have queue size 1 or 2 keeps only
that many undelivered samples and deserializes only those: a subscriber with queue size 1
always gets the newest message, never a backlog. Other topics deliver every sample.
"""

from __future__ import annotations

import contextlib
import logging
import os
import socket
import threading
import time
import weakref
from collections import deque
from collections.abc import Callable
from functools import partial
from typing import Any, cast

import zenoh

from belvedere.graph._endpoints import Publisher, ServiceServer, Subscription, Topic
from belvedere.graph._errors import ServiceFailedError, ServiceUnavailableError
from belvedere.graph._graph import Graph, Node
from belvedere.graph._hosts import HostAccess
from belvedere.graph._zenoh_control import _NodeControl
from belvedere.graph._zenoh_discovery import _Discovery
from belvedere.graph._zenoh_latch import _STAMP, Sent, _LatchedSeen, _sender, _sent
from belvedere.graph._zenoh_outbox import NEWEST_ONLY, TopicStats, _bulky, _Outbox
from belvedere.graph._zenoh_params import _ParamService
from belvedere.graph._zenoh_session import check_domain, domain_endpoint, open_session
from belvedere.graph._zenoh_types import _TypeService
from belvedere.msgs import short, types

__all__ = ["ZenohTransport"]

logger = logging.getLogger("belvedere.transport")


def _prepare(type_name: str) -> None:
    types().prepare(type_name)


def _close_at_exit(ref: weakref.ref[ZenohTransport]) -> None:
    transport = ref()
    if transport is not None:
        transport.close()


class ZenohTransport(_Discovery, _ParamService, _NodeControl, _TypeService):
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
        self.endpoint = HostAccess.from_environment().endpoint(
            endpoint, domain_endpoint(self.domain)
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
        self._control: Any = None
        self._unanswered: dict[str, float] = {}
        self._asker: Callable[[str], bool] | None = None
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
        # Types: every process answers for those it knows, graph or not (a recorder too)
        self._type_queryable = self.session.declare_queryable(
            self._key("y/**"), self._on_type_query
        )
        # a type no package here defines: asked of the other processes before it is unknown
        # (weakly: the registry lives as long as the process, a transport may not)
        method = weakref.WeakMethod(self.ask_type)

        def ask(name: str) -> bool:
            bound = method()
            return bound is not None and bound(name)

        self._asker = ask
        types().add_asker(ask)

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
        self._control = self.session.declare_queryable(self._key("c/**"), self._on_control_query)

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        if self._asker is not None:
            types().remove_asker(self._asker)
        self._outbox.close()
        with contextlib.suppress(zenoh.ZError):
            self.session.close()  # type: ignore[no-untyped-call]

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

    def service_key(self, name: str) -> str:
        """The key a service answers on (where rosservice has the node's rosrpc:// URI)."""
        return self._key("s", name)

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
