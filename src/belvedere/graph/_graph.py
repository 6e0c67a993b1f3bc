"""The graph: nodes, topics, parameters, services, all on one executor.

Inside one process messages pass as objects, never serialized. A transport (Zenoh) carries
them to other processes when someone there wants them.
"""

from __future__ import annotations

import itertools
import logging
import os
import threading
import time
from collections.abc import Callable, Mapping
from typing import Any, Protocol

from belvedere.graph._endpoints import (
    Publisher,
    SeqRule,
    ServiceServer,
    Subscription,
    Topic,
    TopicUse,
)
from belvedere.graph._errors import GraphError, ServiceUnavailableError
from belvedere.graph._executor import NS, Executor, Timer
from belvedere.graph._log import NodeLogger
from belvedere.graph._names import resolve_name
from belvedere.graph._params import ParamTree
from belvedere.msgs import message_from_data, short, types

__all__ = ["Graph", "Node", "Rate", "Transport", "process_node_name"]


class Transport(Protocol):
    """What the graph needs from an inter-process transport."""

    def advertise(self, topic: Topic, publisher: Publisher) -> None: ...
    def unadvertise(self, topic: Topic, publisher: Publisher) -> None: ...
    def subscribe(self, topic: Topic, subscription: Subscription) -> None: ...
    def unsubscribe(self, topic: Topic, subscription: Subscription) -> None: ...
    def send(self, topic: Topic, msg: Any, publisher: Publisher) -> None: ...
    def offer_service(self, server: ServiceServer) -> None: ...
    def withdraw_service(self, server: ServiceServer) -> None: ...
    def call_service(self, name: str, srv_type: str, request: Any, timeout: float) -> Any: ...
    def topic_users(self, topic: str) -> list[tuple[str, str, str]]: ...
    def node_added(self, node: Node) -> None: ...
    def node_removed(self, node: Node) -> None: ...
    def attach(self, graph: Graph) -> None: ...
    def close(self) -> None: ...


class Rate:
    """Sleep to keep a loop at ``hz`` in graph time (for threads other than the executor)."""

    def __init__(self, graph: Graph, hz: float) -> None:
        if hz <= 0:
            msg = f"rate must be positive, got {hz!r} Hz"
            raise ValueError(msg)
        self.graph = graph
        self.period_ns = round(NS / hz)
        self.last_ns = graph.now_ns()

    def sleep(self) -> None:
        target = self.last_ns + self.period_ns
        self.graph.sleep_until_ns(target)
        self.last_ns = max(target, self.graph.now_ns() - self.period_ns)


class Node:
    """A named participant with publishers, subscriptions, timers, params and services."""

    def __init__(
        self,
        graph: Graph,
        name: str,
        namespace: str,
        remappings: Mapping[str, str],
    ) -> None:
        self.graph = graph
        self.name = name
        self.namespace = namespace
        self.remappings = dict(remappings)
        self.publishers: list[Publisher] = []
        self.subscriptions: list[Subscription] = []
        self.services: list[ServiceServer] = []
        self.timers: list[Timer] = []
        self.seqs: dict[str, int] = {}
        """The ``header.seq`` counters of its publications, by topic (ROS 1 counts per topic
        per process: the publishers of one node on one topic share one)."""
        self.logger = NodeLogger(self)
        """Its log: each message on ``/rosout`` and on the terminal, as a ROS node's."""
        self.closed = False
        """Shut down: off the graph, its publishers silent, its callbacks never called."""
        self.shutdown_request: tuple[str, str] | None = None
        """Who asked another process's node to shut down, and why (rosnode kill: "user
        request"); None when it was not asked (replaced by a node of its name)."""
        self.on_crash: Callable[[Exception], None] | None = None
        """Called instead of raising when one of its timers (or a subscription, with a
        belvedere error) raises: the node dies alone, as a process of a launch does."""

    @property
    def full_name(self) -> str:
        return resolve_name(self.name, namespace=self.namespace)

    def resolve(self, name: str) -> str:
        return resolve_name(
            name, namespace=self.namespace, node=self.name, remappings=self.remappings
        )

    def shutdown(self) -> None:
        """Leave the graph: publishers, subscriptions, services and timers go (call on the
        executor thread). A node another process replaced by name is shut down so."""
        if self.closed:
            return
        self.closed = True
        for timer in self.timers:
            timer.cancel()
        graph = self.graph
        for pub in list(self.publishers):
            graph.remove_publisher(pub)
        for sub in list(self.subscriptions):
            graph.remove_subscription(sub)
        for server in list(self.services):
            graph.remove_service(server)
        graph.remove_node(self)

    # --- topics --------------------------------------------------------------------------------
    def publisher(
        self,
        topic: str,
        msg_type: str,
        *,
        queue_size: int = 10,
        latch: bool = False,
        seq_rule: SeqRule = "roscpp",
    ) -> Publisher:
        """``seq_rule``: how ``header.seq`` is numbered (roscpp's or rospy's rule)."""
        t = self.graph.topic(self.resolve(topic), msg_type, use="publish")
        pub = Publisher(self, t, latch=latch, queue_size=queue_size, seq_rule=seq_rule)
        self.publishers.append(pub)
        t.publishers.append(pub)
        if self.graph.transport is not None:
            self.graph.transport.advertise(t, pub)
        return pub

    def subscribe(
        self,
        topic: str,
        msg_type: str,
        callback: Callable[[Any], object],
        *,
        queue_size: int = 10,
    ) -> Subscription:
        t = self.graph.topic(self.resolve(topic), msg_type, use="subscribe")
        sub = Subscription(self, t, callback, queue_size=queue_size)
        self.subscriptions.append(sub)
        t.subscriptions.append(sub)
        for msg in list(t.latched.values()):
            sub.enqueue(msg)
        if self.graph.transport is not None:
            self.graph.transport.subscribe(t, sub)
        return sub

    # --- time ----------------------------------------------------------------------------------
    def timer(
        self, period: float, callback: Callable[[], object], *, oneshot: bool = False
    ) -> Timer:
        timer = self.graph.executor.add_timer(period, self._guarded(callback), oneshot=oneshot)
        self.timers.append(timer)
        return timer

    def _guarded(self, callback: Callable[[], object]) -> Callable[[], object]:
        def run() -> object:
            try:
                return callback()
            except Exception as err:
                if self.on_crash is None:
                    raise
                self.on_crash(err)
                return None

        return run

    def now_ns(self) -> int:
        return self.graph.now_ns()

    def now(self) -> float:
        return self.graph.now_ns() / NS

    # --- parameters ----------------------------------------------------------------------------
    def get_param(self, name: str, default: Any = ...) -> Any:
        return self.graph.params.get(self.resolve(name), default)

    def set_param(self, name: str, value: Any) -> None:
        self.graph.params.set(self.resolve(name), value)

    def has_param(self, name: str) -> bool:
        return self.graph.params.has(self.resolve(name))

    # --- services ------------------------------------------------------------------------------
    def service(
        self,
        name: str,
        srv_type: str,
        handler: Callable[[Any], Any],
        *,
        threaded: bool = False,
    ) -> ServiceServer:
        resolved = self.resolve(name)
        full_type = types().resolve_service(srv_type)
        if resolved in self.graph.services:
            owner = self.graph.services[resolved].node.name
            msg = f"service {resolved} is already offered by {owner}"
            raise GraphError(msg)
        server = ServiceServer(self, resolved, full_type, handler, threaded=threaded)
        self.graph.services[resolved] = server
        self.services.append(server)
        if self.graph.transport is not None:
            self.graph.transport.offer_service(server)
        return server

    def call_service(
        self, name: str, srv_type: str, request: Any = None, *, timeout: float = 5.0
    ) -> Any:
        """Call a service here or in another process; ``request`` may be data or a message."""
        resolved = self.resolve(name)
        full_type = types().resolve_service(srv_type)
        if request is None or isinstance(request, dict | list):
            request = message_from_data(f"{full_type}_Request", request)
        local = self.graph.services.get(resolved)
        if local is not None:
            if local.type != full_type:
                msg = f"service {resolved} is {short(local.type)}, not {short(full_type)}"
                raise GraphError(msg)
            return local.handle(request)
        if self.graph.transport is not None:
            return self.graph.transport.call_service(resolved, full_type, request, timeout)
        msg = f"service {resolved} is not offered by any node"
        raise ServiceUnavailableError(msg, hint="is the node that provides it running?")


_named_in_process = itertools.count()


def process_node_name(base: str) -> str:
    """``base`` made this process's own (``base_<pid>``, then ``base_<pid>_<n>``): a node
    every belvedere process has (its clock, its viewer) must not replace another's by name
    when the processes share a graph."""
    n = next(_named_in_process)
    return f"{base}_{os.getpid()}" + (f"_{n}" if n else "")


class Graph:
    """Nodes, topics, the parameter tree and services on one executor."""

    def __init__(
        self,
        *,
        sim_time: bool = True,
        seed: int = 0,
        transport: Transport | None = None,
        clock_hz: float | None = 100.0,
    ) -> None:
        """``clock_hz``: in simulated time, how often ``/clock`` announces it (None: never)."""
        self.executor = Executor(sim_time=sim_time, seed=seed)
        self.params = ParamTree()
        self.params.set("/use_sim_time", sim_time)
        self.topics: dict[str, Topic] = {}
        self.services: dict[str, ServiceServer] = {}
        self.nodes: dict[str, Node] = {}
        self.shutdown_hooks: list[Callable[[], None]] = []
        """Run first by :meth:`shutdown`, last added first (a bridge leaves before the
        executor stops)."""
        self.transport = transport
        if transport is not None:
            transport.attach(self)
        self._lock = threading.Lock()
        self._seq = 0
        self._clock: Node | None = None
        if sim_time and clock_hz:
            # Named for this process (and graph): another process joining the graph under
            # the same name would replace this node, and its /clock with it.
            clock = self.create_node(process_node_name("belvedere_clock"))
            self._clock = clock
            pub = clock.publisher("/clock", "rosgraph_msgs/Clock", queue_size=1)
            clock_type = types().cls("rosgraph_msgs/Clock")
            time_type = types().cls("builtin_interfaces/Time")

            def tick() -> None:
                if not pub.wanted:
                    return
                ns = self.now_ns()
                pub.publish(clock_type(time_type(ns // NS, ns % NS)))

            clock.timer(1.0 / clock_hz, tick).idle = lambda: not pub.wanted

    # --- time ----------------------------------------------------------------------------------
    @property
    def sim_time(self) -> bool:
        return self.executor.sim_time

    def now_ns(self) -> int:
        return self.executor.now_ns()

    def clock_stamp(self) -> tuple[int, int]:
        ns = self.now_ns()
        return ns // NS, ns % NS

    def follow_clock(self, node: Node) -> Subscription:
        """Take simulated time from the ``/clock`` another process publishes (``node``
        subscribes to it): a graph that joins a running simulation. Needs ``sim_time``."""
        if not self.sim_time:
            msg = "only a graph in simulated time can follow /clock"
            raise GraphError(msg)
        executor = self.executor
        executor.follow()
        if self._clock is not None:  # the time is another's now: only its owner announces it
            self._clock.shutdown()
            self._clock = None

        def tick(msg: Any) -> None:
            executor.set_clock(msg.clock.sec * NS + msg.clock.nanosec)

        return node.subscribe("/clock", "rosgraph_msgs/Clock", tick, queue_size=1)

    def sleep_until_ns(self, target_ns: int) -> None:
        """Block a non-executor thread until graph time reaches ``target_ns``."""
        while self.now_ns() < target_ns and not self.executor.stopped:
            if self.sim_time:
                time.sleep(0.0005)
            else:
                time.sleep(max(0.0, (target_ns - self.now_ns()) / NS))

    def on_executor_thread(self) -> bool:
        thread = self.executor.thread
        return thread is None or thread is threading.current_thread()

    # --- structure -----------------------------------------------------------------------------
    def create_node(
        self,
        name: str,
        *,
        namespace: str = "/",
        remappings: Mapping[str, str] | None = None,
        params: Mapping[str, Any] | None = None,
    ) -> Node:
        """A node. Remapping keys/values are resolved against its namespace; ``params`` are
        its private parameters (``~name``)."""
        ns = "/" + "/".join(p for p in namespace.split("/") if p)
        resolved_remaps = {
            resolve_name(k, namespace=ns, node=name): resolve_name(v, namespace=ns, node=name)
            for k, v in (remappings or {}).items()
        }
        node = Node(self, name, ns, resolved_remaps)
        full = node.full_name
        if full in self.nodes:
            msg = f"a node named {full} already exists in this graph"
            raise GraphError(msg)
        self.nodes[full] = node
        for key, value in (params or {}).items():
            node.set_param(f"~{key}", value)
        if self.transport is not None:
            self.transport.node_added(node)
        return node

    def topic(self, name: str, msg_type: str, *, use: TopicUse = "use") -> Topic:
        """The topic ``name`` of type ``msg_type``; a topic of another type here, or on the
        graph when nobody here uses it yet, is an error (``use``: what the caller was to do
        with it, for the message)."""
        full_type = types().resolve(msg_type)
        with self._lock:
            topic = self.topics.get(name)
        if topic is None or not (topic.publishers or topic.subscriptions):
            if topic is None or topic.type == full_type:
                # Asked once per topic: from then on the topic here has the graph's type.
                self._check_others(name, full_type, use)
            with self._lock:
                topic = self.topics.setdefault(name, Topic(name, full_type))
        if topic.type != full_type:
            msg = (
                f"topic {name} has type {short(topic.type)}; cannot also use it as "
                f"{short(full_type)}"
            )
            raise GraphError(msg)
        return topic

    def _check_others(self, name: str, full_type: str, use: TopicUse) -> None:
        """Refuse a type that other processes' nodes on the topic do not use (ROS 1 would
        connect them, then drop every message)."""
        if self.transport is None:
            return
        others = [u for u in self.transport.topic_users(name) if u[1] != full_type]
        if not others:
            return
        their_type = min(others)[1]
        who = ", ".join(
            f"{node} {'publishes' if kind == 'pub' else 'subscribes to'} it"
            for kind, typ, node in sorted(others)
            if typ == their_type
        )
        ours = short(full_type)
        doing = {
            "publish": f"cannot publish {ours} on it",
            "subscribe": f"cannot subscribe to it as {ours}",
            "use": f"cannot also use it as {ours}",
        }[use]
        msg = f"topic {name} has type {short(their_type)} ({who}); {doing}"
        raise GraphError(msg)

    def remove_publisher(self, pub: Publisher) -> None:
        if pub in pub.topic.publishers:
            pub.topic.publishers.remove(pub)
            pub.topic.latched.pop(pub, None)
            pub.node.publishers.remove(pub)
            if self.transport is not None:
                self.transport.unadvertise(pub.topic, pub)

    def remove_service(self, server: ServiceServer) -> None:
        if self.services.get(server.name) is server:
            del self.services[server.name]
            server.node.services.remove(server)
            if self.transport is not None:
                self.transport.withdraw_service(server)

    def remove_node(self, node: Node) -> None:
        if self.nodes.get(node.full_name) is node:
            del self.nodes[node.full_name]
            if self.transport is not None:
                self.transport.node_removed(node)

    def remove_subscription(self, sub: Subscription) -> None:
        if sub in sub.topic.subscriptions:
            sub.topic.subscriptions.remove(sub)
            sub.node.subscriptions.remove(sub)
            if self.transport is not None:
                self.transport.unsubscribe(sub.topic, sub)

    # --- running -------------------------------------------------------------------------------
    def run(
        self,
        *,
        duration: float | None = None,
        rtf: float | None = None,
        until: Callable[[], bool] | None = None,
    ) -> None:
        """Run the executor on this thread (see :meth:`Executor.run`)."""
        self.executor.run(duration=duration, rtf=rtf, until=until)

    def spin_once(self) -> None:
        self.executor.spin_once()

    def start(self, *, rtf: float | None = 1.0) -> threading.Thread:
        """Run the executor on a background thread (stop with :meth:`shutdown`)."""
        ready = threading.Event()

        def main() -> None:
            self.executor.thread = threading.current_thread()
            ready.set()
            self.executor.run(rtf=rtf)

        thread = threading.Thread(target=main, name="belvedere-executor", daemon=True)
        thread.start()
        ready.wait()
        return thread

    def shutdown(self) -> None:
        while self.shutdown_hooks:
            hook = self.shutdown_hooks.pop()
            try:
                hook()
            except Exception:  # one hook's failure must not keep the graph running
                logging.getLogger(__name__).exception("a shutdown hook failed")
        self.executor.stop()
        if self.transport is not None:
            self.transport.close()
