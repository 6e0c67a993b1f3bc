"""The graph's side of ROS 1: one slave API and one TCPROS port for every graph node.

- A ROS 1 subscriber of a topic the graph publishes is given this bridge as a publisher: it
  asks the slave API for the topic (``requestTopic``), connects to the TCPROS port, and each
  connection becomes a subscription on the graph whose messages are written as ROS 1 bytes.
- A topic ROS 1 programs publish and a graph node subscribes to is read from each ROS 1
  publisher over TCPROS and published on the graph by the bridge's node (a type the graph
  does not know is learnt from the connection's ``message_definition``).
- A ROS 1 call of a graph service arrives on the TCPROS port (``rosrpc://``) and is made on
  the graph.

Who is on the graph is looked at every :data:`LOOK_S` (and at once when a ROS 1 program
registers), so ROS 1 subscribers are told of a new graph publisher within that time."""

from __future__ import annotations

import contextlib
import itertools
import logging
import os
import socket
import threading
import time
import xmlrpc.client
from collections import deque
from dataclasses import dataclass, field
from functools import partial
from typing import Any, Final
from urllib.parse import quote, unquote

from belvedere.errors import BelvedereError
from belvedere.graph import Graph, Publisher, Subscription, ZenohTransport
from belvedere.msgs import canonical, learn_full_text, ros1_name, ros1_text, types
from belvedere.ros1wire._master import MasterSide, Registrations
from belvedere.ros1wire._services import ServiceSide
from belvedere.ros1wire._tcpros import (
    FrameReader,
    TcprosError,
    read_header,
    write_frames,
    write_header,
)
from belvedere.ros1wire._xmlrpc import XmlRpcServer, request_path, server_proxy

__all__ = ["BRIDGE_NODE", "Ros1Bridge"]

logger = logging.getLogger("belvedere.ros1wire")

BRIDGE_NODE: Final = "belvedere_ros1_bridge"
LOOK_S: Final = 0.25
MAX_RETRY_S: Final = 10.0
RETIRE_S: Final = 5.0
OUT_QUEUE: Final = 100
"""Messages waiting for one ROS 1 subscriber; past this the oldest are dropped, as a
roscpp publisher's queue does."""
IN_QUEUE: Final = 1000
"""Messages read from a topic's ROS 1 publishers and not yet published on the graph; past
this the oldest are dropped (the executor is behind: a graph subscription's queue would drop
them too), so a stalled executor does not grow this process without end."""
_connection_ids = itertools.count(1)


@dataclass
class _Outlet:
    """One ROS 1 subscriber's connection to a graph topic."""

    id: int
    topic: str
    caller: str
    sock: socket.socket
    queue: deque[Any] = field(default_factory=lambda: deque(maxlen=OUT_QUEUE))
    ready: threading.Condition = field(default_factory=threading.Condition)
    subscription: Subscription | None = None
    closed: bool = False


@dataclass
class _Inlet:
    """A topic ROS 1 publishes that graph nodes subscribe to."""

    topic: str
    ros1_type: str
    publisher: Publisher | None = None
    advertised: bool = False
    sources: dict[str, socket.socket | None] = field(default_factory=dict)
    """publisher's slave API → its connection (None while connecting)"""
    closed: bool = False
    waiting: deque[Any] = field(default_factory=lambda: deque(maxlen=IN_QUEUE))
    """Messages read and not yet published on the graph: one executor job publishes all
    that came in meanwhile, not one job each."""
    posted: bool = False
    lock: threading.Lock = field(default_factory=threading.Lock)
    retiring: bool = False
    unregistered: bool = False
    """The graph publisher is gone for good (set on the executor, after the last publish)."""
    """No ROS 1 program publishes the topic now: its connections are read to their end."""


class Ros1Bridge(ServiceSide):
    """Serve the graph to ROS 1 programs registered with ``master`` (and tell it so)."""

    def __init__(self, graph: Graph, master: MasterSide, host: str = "127.0.0.1") -> None:
        self.graph = graph
        self.master = master
        self.host = host
        self.node = graph.create_node(f"{BRIDGE_NODE}_{os.getpid()}")
        self.caller_id = self.node.full_name
        self.slave = XmlRpcServer(host, 0, self._slave)
        self.uri = self.slave.uri
        self._listener = socket.create_server((host, 0))
        self.port = int(self._listener.getsockname()[1])
        self._state = Registrations()
        self._lock = threading.Lock()
        self._outlets: dict[int, _Outlet] = {}
        self._inlets: dict[str, _Inlet] = {}
        self._stop = threading.Event()
        self._wake = threading.Event()
        self._failed: dict[tuple[str, str], tuple[float, float]] = {}
        """(topic, ROS 1 publisher's API) that could not be reached → (when to try again,
        the wait after that): a publisher that died without unregistering stays registered,
        as with roscore, and is tried less and less often, with one warning."""
        self._probed: set[tuple[str, str]] = set()
        """(topic or service, its ROS 1 publisher's or server's URI) already asked"""
        self._offered: dict[str, Any] = {}
        """ROS 1 services offered on the graph by the bridge's node: name → its server"""
        self._look()
        master.attach(self)
        threading.Thread(target=self._accept, name="belvedere-tcpros", daemon=True).start()
        threading.Thread(target=self._keep_looking, name="belvedere-ros1-look", daemon=True).start()

    def close(self) -> None:
        self._stop.set()
        self._wake.set()
        self.slave.close()
        self._listener.close()
        with self._lock:
            outlets, inlets = list(self._outlets.values()), list(self._inlets.values())
        for outlet in outlets:
            self._close_outlet(outlet)
        for inlet in inlets:
            self._close_inlet(inlet)

    # --- what the master asks ----------------------------------------------------------------
    def graph_state(self) -> Registrations:
        with self._lock:
            return self._state

    def node_uri(self, node: str) -> str:
        """A graph node's slave URI: the bridge's, with the node's name as its path (what
        ``shutdown`` is asked of is then known)."""
        return self.uri + quote(node.lstrip("/"), safe="/")

    def service_uri(self) -> str:
        return f"rosrpc://{self.host}:{self.port}"

    def ros1_changed(self, topic: str) -> None:
        self._wake.set()

    # --- who is on the graph ------------------------------------------------------------------
    def _look(self) -> None:
        transport = self.graph.transport
        state = Registrations()
        if isinstance(transport, ZenohTransport):
            try:
                info = transport.info(timeout=0.5)
            except BelvedereError as err:
                logger.debug("ros1: cannot look at the graph: %s", err.message)
                return
            own = self.caller_id
            for table, into in (
                (info.publishers, state.publishers),
                (info.subscribers, state.subscribers),
            ):
                for topic, users in table.items():
                    for typ, node in users:
                        if node != own:
                            into.setdefault(topic, {})[node] = ros1_name(typ)
            for service, providers in info.services.items():
                for typ, node in providers:
                    if node != own:
                        state.services.setdefault(service, {})[node] = typ
            state.nodes = {n: self.node_uri(n) for n in info.nodes if n != own}
        with self._lock:
            before, self._state = self._state, state
        self.master.graph_changed(before, state)
        self._reconcile_inlets(state)
        self._learn_new_types()
        self._reconcile_services(state)

    def _keep_looking(self) -> None:
        while not self._stop.is_set():
            self._wake.wait(LOOK_S)
            self._wake.clear()
            if self._stop.is_set():
                return
            try:
                self._look()
            except Exception:  # the bridge must outlive one bad look
                logger.exception("ros1: looking at the graph failed")

    # --- ROS 1 publishers → the graph ----------------------------------------------------------
    def _reconcile_inlets(self, state: Registrations) -> None:
        """Each topic ROS 1 programs publish is advertised on the graph by the bridge's node
        (so belvedere's tools list it with its type); its publishers are read only while a
        graph node subscribes."""
        ros1 = self.master.ros1_view()
        published = {t: users for t, users in ros1.publishers.items() if users}
        apis = ros1.nodes
        with self._lock:
            gone = [i for t, i in self._inlets.items() if t not in published]
            for inlet in gone:
                del self._inlets[inlet.topic]
        for inlet in gone:
            self._retire_inlet(inlet)
        for topic, users in published.items():
            typ = next(iter(users.values()))
            with self._lock:
                inlet = self._inlets.setdefault(topic, _Inlet(topic, typ))
            if not inlet.advertised and _known(typ):
                inlet.advertised = True
                store_type = types().resolve(typ)
                self.graph.executor.post(partial(self._open_publisher, inlet, store_type, False))
            if not state.subscribers.get(topic):
                self._drop_sources(inlet)
                continue
            with self._lock:
                for node in users:
                    api = apis.get(node)
                    retry = self._failed.get((topic, api or ""))
                    if retry is not None and time.monotonic() < retry[0]:
                        continue
                    if api is not None and api not in inlet.sources:
                        inlet.sources[api] = None
                        threading.Thread(
                            target=self._read_from,
                            args=(inlet, api),
                            name="belvedere-tcpros-in",
                            daemon=True,
                        ).start()

    def _drop_sources(self, inlet: _Inlet) -> None:
        """Stop reading a topic nobody on the graph listens to (its readers end)."""
        with self._lock:
            socks = [s for s in inlet.sources.values() if s is not None]
        for sock in socks:
            with contextlib.suppress(OSError):
                sock.shutdown(socket.SHUT_RDWR)

    def _read_from(self, inlet: _Inlet, api: str) -> None:
        try:
            sock, header = self._connect(inlet, api)
        except (OSError, TcprosError, xmlrpc.client.Error, BelvedereError) as err:
            with self._lock:
                inlet.sources.pop(api, None)
                before = self._failed.get((inlet.topic, api))
                wait = min(2 * before[1], MAX_RETRY_S) if before else LOOK_S
                self._failed[inlet.topic, api] = (time.monotonic() + wait, wait)
            if before is None:
                logger.warning("ros1: cannot subscribe to %s at %s: %s", inlet.topic, api, err)
            return
        with self._lock:
            self._failed.pop((inlet.topic, api), None)
        try:
            store_type = self._learn(header, inlet)
            latched = header.get("latching", "0") == "1"
            self.graph.executor.post(partial(self._open_publisher, inlet, store_type, latched))
            message = types().ros1_reader(store_type, borrowed=True)
            reader = FrameReader(sock)
            # each read brings all the publisher wrote meanwhile: its messages go to the
            # executor together, for one job and one lock, not one each (the reads end, with
            # an OSError, when the sources are dropped)
            while not inlet.closed:
                msgs = reader.batch(message)
                with inlet.lock:
                    inlet.waiting.extend(msgs)
                    post, inlet.posted = not inlet.posted, True
                if post:
                    self.graph.executor.post(partial(self._publish, inlet))
        except (OSError, TcprosError) as err:
            if not inlet.closed:
                logger.debug("ros1: %s from %s ended: %s", inlet.topic, api, err)
        except Exception as err:  # noqa: BLE001 (a publisher sent something else)
            logger.warning("ros1: a message on %s from %s is unreadable: %s", inlet.topic, api, err)
        finally:
            sock.close()
            with self._lock:
                inlet.sources.pop(api, None)
                last = inlet.retiring and not inlet.sources
            if last:
                self._close_inlet(inlet)

    def _connect(self, inlet: _Inlet, api: str) -> tuple[socket.socket, dict[str, str]]:
        answer: Any = server_proxy(api, timeout=5.0).requestTopic(
            self.caller_id, inlet.topic, [["TCPROS"]]
        )
        code, status, protocol = answer
        if code != 1 or not protocol or protocol[0] != "TCPROS":
            msg = f"requestTopic answered {status!r}"
            raise TcprosError(msg)
        sock = socket.create_connection((protocol[1], int(protocol[2])), timeout=10.0)
        sock.settimeout(None)
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        with self._lock:
            inlet.sources[api] = sock
        md5, definition = "*", ""
        try:
            known = types().resolve(inlet.ros1_type)
            md5, definition = ros1_text(known).md5sum, ros1_text(known).full_text
        except BelvedereError:
            pass
        write_header(
            sock,
            {
                "callerid": self.caller_id,
                "topic": inlet.topic,
                "type": inlet.ros1_type,
                "md5sum": md5,
                "message_definition": definition,
                "tcp_nodelay": "1",
            },
        )
        header = read_header(sock)
        if "error" in header:
            sock.close()
            raise TcprosError(header["error"])
        return sock, header

    def _learn(self, header: dict[str, str], inlet: _Inlet) -> str:
        """The store name of the connection's type, learnt from its definition if new."""
        ros1_type = header.get("type", inlet.ros1_type)
        try:
            return types().resolve(ros1_type)
        except BelvedereError:
            where = f"{inlet.topic} (from {header.get('callerid', 'a ROS 1 node')})"
            learn_full_text(
                header.get("message_definition", ""),
                canonical(ros1_type),
                header.get("md5sum", "*"),
                where,
            )
            return types().resolve(ros1_type)

    def _learn_new_types(self) -> None:
        """Ask each ROS 1 publisher of a type the graph does not know for its definition
        (the connection header has it), so graph nodes can subscribe to the topic."""
        ros1 = self.master.ros1_view()
        published = [
            (topic, typ, ros1.nodes.get(node))
            for topic, users in ros1.publishers.items()
            for node, typ in users.items()
        ]
        for topic, typ, api in published:
            if api is None or (topic, api) in self._probed or _known(typ):
                continue
            self._probed.add((topic, api))
            threading.Thread(
                target=self._probe_topic,
                args=(_Inlet(topic, typ), api),
                name="belvedere-tcpros-probe",
                daemon=True,
            ).start()

    def _probe_topic(self, probe: _Inlet, api: str) -> None:
        try:
            sock, header = self._connect(probe, api)
            sock.close()
            self._learn(header, probe)
        except (OSError, TcprosError, xmlrpc.client.Error, BelvedereError, ValueError) as err:
            text = err.message if isinstance(err, BelvedereError) else str(err)
            logger.warning("ros1: cannot learn %s's type from %s: %s", probe.topic, api, text)

    def _open_publisher(self, inlet: _Inlet, store_type: str, latched: bool) -> None:
        # not "closed": messages read before the inlet closed are still to be published by
        # jobs behind this one; only the unregistering job, after them, ends the publisher
        if inlet.publisher is None and not inlet.unregistered:
            inlet.publisher = self.node.publisher(inlet.topic, store_type, latch=latched)

    def _publish(self, inlet: _Inlet) -> None:
        with inlet.lock:
            batch = list(inlet.waiting)
            inlet.waiting.clear()
            inlet.posted = False
        # what was read before the inlet closed still goes out: its publisher is unregistered
        # by a job posted after these
        if inlet.publisher is not None:
            for msg in batch:
                inlet.publisher.publish(msg)

    def _retire_inlet(self, inlet: _Inlet) -> None:
        """A topic no ROS 1 program publishes any more. What its publishers sent before they
        went is read to the end of their connections (a bag played, then rosbag ended: the
        master may say so before the last messages are read), then the inlet closes; a
        connection still open after RETIRE_S is dropped."""
        with self._lock:
            inlet.retiring = True
            busy = bool(inlet.sources)
        if not busy:
            self._close_inlet(inlet)
            return
        timer = threading.Timer(RETIRE_S, self._close_inlet, (inlet,))
        timer.daemon = True
        timer.start()

    def _close_inlet(self, inlet: _Inlet) -> None:
        with self._lock:
            if inlet.closed:
                return
            inlet.closed = True
        self._drop_sources(inlet)

        def unregister() -> None:
            inlet.unregistered = True
            publisher, inlet.publisher = inlet.publisher, None
            if publisher is not None:
                publisher.unregister()

        self.graph.executor.post(unregister)

    # --- TCPROS: ROS 1 subscribers and service clients ------------------------------------
    def _accept(self) -> None:
        while not self._stop.is_set():
            try:
                sock, _ = self._listener.accept()
            except OSError:
                return
            threading.Thread(
                target=self._serve, args=(sock,), name="belvedere-tcpros-out", daemon=True
            ).start()

    def _serve(self, sock: socket.socket) -> None:
        try:
            sock.settimeout(10.0)
            header = read_header(sock)
            sock.settimeout(None)
            if "service" in header:
                self._serve_service(sock, header)
            elif "topic" in header:
                self._serve_topic(sock, header)
            else:
                write_header(sock, {"error": "neither a topic nor a service was asked for"})
        except (OSError, TcprosError) as err:
            logger.debug("ros1: a TCPROS connection ended: %s", err)
        finally:
            sock.close()

    def _serve_topic(self, sock: socket.socket, header: dict[str, str]) -> None:
        topic, caller = header["topic"], header.get("callerid", "")
        users = self.graph_state().publishers.get(topic)
        if not users:
            write_header(
                sock,
                {
                    "error": f"received a connection for a nonexistent topic [{topic}] from "
                    f"[{_connection_info(sock)}] [{caller}]."
                },
            )
            return
        ros1_type = next(iter(users.values()))
        store_type = types().resolve(ros1_type)
        text = ros1_text(store_type)
        wanted = header.get("md5sum", "*")
        if wanted not in ("*", text.md5sum):
            write_header(
                sock,
                {
                    "error": f"Client [{caller}] wants topic {topic} to have datatype/md5sum "
                    f"[{header.get('type', '')}/{wanted}], but our version has "
                    f"[{ros1_type}/{text.md5sum}]. Dropping connection."
                },
            )
            return
        write_header(
            sock,
            {
                "callerid": sorted(users)[0],
                "md5sum": text.md5sum,
                "type": ros1_type,
                "latching": "1" if self._latches(topic) else "0",
                "message_definition": text.full_text,
                "topic": topic,
            },
        )
        if header.get("tcp_nodelay") == "1":
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        outlet = _Outlet(next(_connection_ids), topic, caller, sock)
        with self._lock:
            self._outlets[outlet.id] = outlet
        self.graph.executor.post(partial(self._subscribe, outlet, store_type))
        parts = types().ros1_parts
        try:
            while not outlet.closed and not self._stop.is_set():
                with outlet.ready:
                    while not outlet.queue and not outlet.closed:
                        outlet.ready.wait(1.0)
                    batch = list(outlet.queue)
                    outlet.queue.clear()
                write_frames(sock, (parts(msg, store_type) for msg in batch))
        finally:
            self._close_outlet(outlet)

    def _latches(self, topic: str) -> bool:
        """Whether a publisher of ``topic`` in this process latches (rosbag record keeps the
        flag, and its play latches again). One in another process is not known here: 0."""
        found = self.graph.topics.get(topic)
        return found is not None and any(pub.latch for pub in list(found.publishers))

    def _subscribe(self, outlet: _Outlet, store_type: str) -> None:
        if outlet.closed:
            return

        def take(msg: Any) -> None:
            with outlet.ready:
                outlet.queue.append(msg)
                outlet.ready.notify()

        outlet.subscription = self.node.subscribe(
            outlet.topic, store_type, take, queue_size=OUT_QUEUE
        )

    def _close_outlet(self, outlet: _Outlet) -> None:
        with outlet.ready:
            outlet.closed = True
            outlet.ready.notify()
        with self._lock:
            self._outlets.pop(outlet.id, None)
        subscription = outlet.subscription
        if subscription is not None:
            self.graph.executor.post(subscription.unregister)

    # --- the slave API -------------------------------------------------------------------------
    def _slave(self, method: str, params: tuple[Any, ...]) -> Any:
        state = self.graph_state()
        if method == "requestTopic":
            protocols = params[2] if len(params) > 2 else []
            if not any(p and p[0] == "TCPROS" for p in protocols):
                return [0, "no supported protocol implementations", []]
            return [1, f"ready on {self.host}:{self.port}", ["TCPROS", self.host, self.port]]
        if method == "getPid":
            return [1, "", os.getpid()]
        if method == "getMasterUri":
            return [1, "", self.master.uri]
        if method == "getPublications":
            return [1, "publications", _listing(state.publishers)]
        if method == "getSubscriptions":
            return [1, "subscriptions", _listing(state.subscribers)]
        if method == "getBusStats":
            return [1, "", [[], [], []]]
        if method == "getBusInfo":
            with self._lock:
                out = [
                    [o.id, o.caller, "o", "TCPROS", o.topic, True, ""]
                    for o in self._outlets.values()
                ]
            return [1, "bus info", out]
        if method == "publisherUpdate" and len(params) >= 3:
            self.master.publishers_updated(str(params[1]), [str(u) for u in params[2]])
            self._wake.set()
            return [1, "", 0]
        if method in ("paramUpdate", "publisherUpdate"):
            return [1, "", 0]
        if method == "shutdown":
            return self._shutdown(unquote(request_path()), state, str(params[0] if params else ""))
        msg = f'method "{method}" is not supported'
        raise xmlrpc.client.Fault(1, msg)

    def _shutdown(self, node: str, state: Registrations, caller: str) -> Any:
        """rosnode kill of a graph node: its process is asked to shut it down, as ``belvedere
        node kill`` asks it."""
        transport = self.graph.transport
        if node not in state.nodes or not isinstance(transport, ZenohTransport):
            return [1, "shutdown", 0]  # the bridge itself, or a node already gone
        if transport.node_request(node, "kill", caller=caller, timeout=5.0) is None:
            return [0, f"{node}'s process did not answer", 0]
        self._wake.set()
        return [1, "shutdown", 0]


def _connection_info(sock: socket.socket) -> str:
    """How roscpp names a TCPROS connection in its messages."""
    try:
        port = sock.getsockname()[1]
        host, peer_port = sock.getpeername()[:2]
    except OSError:
        return "TCPROS connection"
    return f"TCPROS connection on port {port} to [{host}:{peer_port} on socket {sock.fileno()}]"


def _known(ros1_type: str) -> bool:
    try:
        types().resolve(ros1_type)
    except BelvedereError:
        return False
    return True


def _listing(table: dict[str, dict[str, str]]) -> list[list[str]]:
    return [[topic, next(iter(users.values()))] for topic, users in sorted(table.items()) if users]
