"""The Zenoh transport: topics, latched topics, services, parameters and introspection
across processes, CDR-encoded as ROS 2 sends them.

Default: localhost only, no scouting. The first process listens on the well-known endpoint
(``tcp/127.0.0.1:7450``, or ``BELVEDERE_ENDPOINT``); later ones connect to it. Opening to
other machines is explicit (``listen_on`` another address). Messages are serialized only when
a subscriber in another process wants them. Publications use BLOCK congestion control, so
commands are never silently dropped.

Key expressions: ``bv/t/<topic>`` data; ``bv/l/<topic>`` each latching publisher's last
message; ``bv/s/<service>`` service calls; ``bv/p`` parameters; liveliness tokens under
``bv/g/…`` say which node publishes, subscribes or serves what, with which type.
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import threading
from collections import deque
from collections.abc import Callable
from functools import partial
from typing import Any, Final, cast

import zenoh

from belvedere.errors import BelvedereError
from belvedere.graph._graph import (
    Graph,
    GraphError,
    Node,
    Publisher,
    ServiceServer,
    Subscription,
    Topic,
)
from belvedere.msgs import types

__all__ = [
    "DEFAULT_ENDPOINT",
    "GraphInfo",
    "TransportError",
    "ZenohTransport",
    "decode_key",
    "encode_key",
]

logger = logging.getLogger("belvedere.transport")

DEFAULT_ENDPOINT: Final = "tcp/127.0.0.1:7450"


class TransportError(BelvedereError):
    """The transport could not start, or a remote call failed."""


def encode_key(name: str) -> str:
    """One key-expression chunk for a graph name or type (``/a/b`` → ``%a%b``)."""
    return name.replace("/", "%") or "%"


def decode_key(chunk: str) -> str:
    return chunk.replace("%", "/")


def _topic_key(name: str) -> str:
    return "bv/t" + name  # names start with '/'


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
    endpoint = endpoint or os.environ.get("BELVEDERE_ENDPOINT") or DEFAULT_ENDPOINT
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
    raise TransportError(msg, hint="set BELVEDERE_ENDPOINT (or --endpoint) to a free port")


class GraphInfo:
    """Who is on the graph, across processes (from liveliness tokens)."""

    def __init__(self) -> None:
        self.nodes: set[str] = set()
        self.publishers: dict[str, set[tuple[str, str]]] = {}
        """topic → {(type, node)}"""
        self.subscribers: dict[str, set[tuple[str, str]]] = {}
        self.services: dict[str, set[tuple[str, str]]] = {}

    def topic_type(self, topic: str) -> str | None:
        for table in (self.publishers, self.subscribers):
            for typ, _ in sorted(table.get(topic, ())):
                return typ
        return None


class ZenohTransport:
    """Carries a graph's traffic to and from other processes."""

    def __init__(
        self,
        *,
        endpoint: str | None = None,
        role: str = "auto",
        serve_params: bool = True,
    ) -> None:
        self.session, self.role = open_session(endpoint, role=role)
        self.serve_params = serve_params
        self.graph: Graph | None = None
        self._zid = str(self.session.zid())
        self._store = types().store
        self._publishers: dict[str, Any] = {}
        self._matching: dict[str, Any] = {}
        self._subscribers: dict[str, Any] = {}
        self._latch_queryables: dict[str, Any] = {}
        self._service_queryables: dict[str, Any] = {}
        self._tokens: dict[tuple[str, ...], Any] = {}
        self._param_queryable: Any = None
        self._lock = threading.Lock()
        self._closed = False

    # --- lifecycle -----------------------------------------------------------------------------
    def attach(self, graph: Graph) -> None:
        self.graph = graph
        if self.serve_params:
            self._param_queryable = self.session.declare_queryable("bv/p", self._on_param_query)

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        with contextlib.suppress(zenoh.ZError):
            self.session.close()  # type: ignore[no-untyped-call]

    def _token(self, *parts: str) -> None:
        key = tuple(parts)
        if key not in self._tokens:
            expr = "bv/g/" + "/".join(encode_key(p) for p in parts) + "/" + self._zid
            self._tokens[key] = self.session.liveliness().declare_token(expr)

    def _drop_token(self, *parts: str) -> None:
        token = self._tokens.pop(tuple(parts), None)
        if token is not None:
            token.undeclare()

    # --- topics --------------------------------------------------------------------------------
    def node_added(self, node: Node) -> None:
        self._token("node", node.full_name)

    def advertise(self, topic: Topic, publisher: Publisher) -> None:
        self._token("pub", topic.name, topic.type, publisher.node.full_name)
        with self._lock:
            if topic.name in self._publishers:
                return
            zpub = self.session.declare_publisher(
                _topic_key(topic.name),
                congestion_control=zenoh.CongestionControl.BLOCK,
                allowed_destination=zenoh.Locality.REMOTE,
            )
            self._publishers[topic.name] = zpub

            def matching(status: Any) -> None:
                topic.remote = bool(status.matching)

            self._matching[topic.name] = zpub.declare_matching_listener(matching)
            # (zenoh's type stubs call this a bool; it is a MatchingStatus)
            topic.remote = bool(cast(Any, zpub).matching_status.matching)
        if publisher.latch and topic.name not in self._latch_queryables:

            def latched(query: Any) -> None:
                for msg in list(topic.latched.values()):
                    query.reply(
                        "bv/l" + topic.name,
                        types().serialize(msg),
                        attachment=topic.type.encode(),
                    )

            self._latch_queryables[topic.name] = self.session.declare_queryable(
                "bv/l" + topic.name, latched
            )

    def unadvertise(self, topic: Topic, publisher: Publisher) -> None:
        self._drop_token("pub", topic.name, topic.type, publisher.node.full_name)

    def send(self, topic: Topic, msg: Any) -> None:
        zpub = self._publishers.get(topic.name)
        if zpub is not None:
            zpub.put(bytes(self._store.serialize_cdr(msg, topic.type)))

    def subscribe(self, topic: Topic, subscription: Subscription) -> None:
        self._token("sub", topic.name, topic.type, subscription.node.full_name)
        graph = self.graph
        assert graph is not None
        with self._lock:
            if topic.name in self._subscribers:
                return

            def deliver(msg: Any) -> None:
                for sub in list(topic.subscriptions):
                    sub.enqueue(msg)

            # Samples arrive on Zenoh's thread: queue their bytes and wake the executor once
            # per burst, not once per message.
            arrived: deque[bytes] = deque()
            scheduled = [False]

            def flush() -> None:
                scheduled[0] = False
                while arrived:
                    data = arrived.popleft()
                    try:
                        msg = types().deserialize(data, topic.type)
                    except Exception as err:  # noqa: BLE001 (a peer sent something else)
                        logger.warning(
                            "dropped a message on %s that is not a %s: %s",
                            topic.name,
                            topic.type,
                            err,
                        )
                        continue
                    deliver(msg)
                    graph.executor.run_ready()  # each message's callbacks run before the next

            def on_sample(sample: Any) -> None:
                arrived.append(sample.payload.to_bytes())
                if not scheduled[0]:
                    scheduled[0] = True
                    graph.executor.post(flush)

            self._subscribers[topic.name] = self.session.declare_subscriber(
                _topic_key(topic.name), on_sample, allowed_origin=zenoh.Locality.REMOTE
            )
        # A late subscriber gets the last latched message from other processes.
        threading.Thread(target=self._fetch_latched, args=(topic, deliver), daemon=True).start()

    def _fetch_latched(self, topic: Topic, deliver: Callable[[Any], None]) -> None:
        graph = self.graph
        assert graph is not None
        try:
            # Every latching publisher replies under the same key: keep them all.
            replies = self.session.get(
                "bv/l" + topic.name,
                timeout=2.0,
                consolidation=zenoh.ConsolidationMode.NONE,
            )
            for reply in replies:
                if reply.ok is None:
                    continue
                msg = types().deserialize(reply.ok.payload.to_bytes(), topic.type)
                graph.executor.post(partial(deliver, msg))
        except zenoh.ZError:
            pass

    def unsubscribe(self, topic: Topic, subscription: Subscription) -> None:
        self._drop_token("sub", topic.name, topic.type, subscription.node.full_name)

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

            graph.executor.post(run)
            if not done.wait(30.0):
                query.reply_err(b"service handler did not answer within 30 s")
                return
            if isinstance(result[0], Exception):
                query.reply_err(str(result[0]).encode())
            else:
                query.reply("bv/s" + server.name, result[0])

        self._service_queryables[server.name] = self.session.declare_queryable(
            "bv/s" + server.name, on_query
        )

    def call_service(self, name: str, srv_type: str, request: Any, timeout: float) -> Any:
        replies = self.session.get(
            "bv/s" + name,
            payload=types().serialize(request),
            timeout=timeout,
            target=zenoh.QueryTarget.BEST_MATCHING,
        )
        for reply in replies:
            if reply.ok is not None:
                return types().deserialize(reply.ok.payload.to_bytes(), f"{srv_type}_Response")
            if reply.err is not None:
                why = reply.err.payload.to_bytes().decode(errors="replace")
                msg = f"service {name} failed: {why}"
                raise GraphError(msg)
        msg = f"service {name} is not offered by any node (waited {timeout:g} s)"
        raise GraphError(msg, hint="is the node that provides it running?")

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
        query.reply("bv/p", json.dumps(reply).encode())

    def param_request(self, request: dict[str, Any], timeout: float = 2.0) -> Any:
        """Ask the graph that holds the parameters (another process)."""
        replies = self.session.get("bv/p", payload=json.dumps(request).encode(), timeout=timeout)
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
        for reply in self.session.liveliness().get("bv/g/**", timeout=timeout):
            if reply.ok is None:
                continue
            parts = str(reply.ok.key_expr).split("/")[2:-1]
            kind, names = parts[0], [decode_key(p) for p in parts[1:]]
            if kind == "node":
                info.nodes.add(names[0])
            elif kind in ("pub", "sub", "srv") and len(names) == 3:
                table = {"pub": info.publishers, "sub": info.subscribers, "srv": info.services}[
                    kind
                ]
                table.setdefault(names[0], set()).add((names[1], names[2]))
                info.nodes.add(names[2])
        return info
