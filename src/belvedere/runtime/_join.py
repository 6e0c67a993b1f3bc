"""Joining a graph: the transport to it, a graph on a running one (its parameters, its time),
and a tool's small graph of its own, joined to the others by Zenoh."""

from __future__ import annotations

import _thread
import logging
import os
import sys
import threading
import time
from dataclasses import dataclass, field
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph import (
    Graph,
    GraphError,
    GraphInfo,
    Node,
    ZenohTransport,
    graph_running,
)

__all__ = [
    "GraphAddress",
    "Tool",
    "holds_parameters",
    "join_graph",
    "join_ros_master",
    "open_tool",
    "open_transport",
    "running_params",
    "wait_for",
    "wait_for_messages",
]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class GraphAddress:
    """Which graph to join (the command line's ``--domain`` and ``--endpoint``); None for
    either: ``BELVEDERE_DOMAIN``/``BELVEDERE_ENDPOINT``, else domain 0's endpoint."""

    endpoint: str | None = None
    """A Zenoh endpoint (``tcp/127.0.0.1:7450``)."""
    domain: int | None = None
    """A domain number: domain N meets on ``tcp/127.0.0.1:<7450+N>``."""
    ros_master: str | None = None
    """A running ROS 1 master (``http://host:11311``) the graph also joins, its nodes
    registered there as a ROS 1 node (``--ros-master``)."""


def open_transport(address: GraphAddress, **options: Any) -> ZenohTransport:
    """Join the graph at ``address``, and say which (one line on stderr; ``-q`` hides it).
    ``options``: :class:`~belvedere.graph.ZenohTransport`'s."""
    transport = ZenohTransport(endpoint=address.endpoint, domain=address.domain, **options)
    how = "listening" if transport.role == "listen" else "connected"
    logger.info("graph: domain %d (%s, %s)", transport.domain, transport.endpoint, how)
    return transport


@dataclass
class Tool:
    """A tool's graph (``belvedere topic``, ``tf``, ``param`` …): one anonymous node on it.

    A tool ends when its node is asked to (``node kill``), as rostopic ends on ``rosnode
    kill``: it prints rospy's ``shutdown request: user request`` and its main thread is
    interrupted as by Ctrl-C; a verb that sees :attr:`ended_by` set then exits 0, as
    rostopic does."""

    graph: Graph
    transport: ZenohTransport
    node: Node
    ended_by: str | None = None
    """Why the tool's node was shut down from outside ("user request"), if it was."""
    _closing: threading.Event = field(default_factory=threading.Event)
    _lock: threading.Lock = field(default_factory=threading.Lock)

    def info(self, timeout: float = 0.5) -> GraphInfo:
        return self.transport.info(timeout=timeout)

    def wait_for_clock(self, timeout: float = 2.0) -> None:
        """In a simulation's time, until its ``/clock`` has been heard (the graph's time
        reads 0 before: a stamp of "now" would be 0). The executor must be running."""
        if self.graph.executor.following:
            wait_for(lambda: self.graph.now_ns() > 0, timeout, step=0.01)

    def close(self) -> None:
        with self._lock:  # the node the tool closes itself is no request to end
            self._closing.set()
        self.graph.shutdown()

    def _end_when_asked(self) -> None:
        """rospy's watch of its node: once shut down from outside, end the tool."""
        while not self._closing.wait(WATCH_S):
            with self._lock:
                if self._closing.is_set() or not self.node.closed:
                    continue
                asked = self.node.shutdown_request
                self.ended_by = asked[1] if asked else "new node registered with same name"
                sys.stdout.write(f"shutdown request: {self.ended_by}\n")  # as rospy says it
                sys.stdout.flush()
                _thread.interrupt_main()  # wherever the verb waits, as Ctrl-C ends it
                return


WATCH_S = 0.2
"""How often a tool looks whether its node was shut down (rospy's watcher looks as often)."""


def open_tool(address: GraphAddress, kind: str) -> Tool:
    """A graph with one anonymous node (``belvedere_KIND_PID``), connected (or listening) on
    the endpoint, in the running graph's time (following its ``/clock`` when it simulates
    time, as rostopic and tf_echo do under ``/use_sim_time``), else the wall clock's."""
    transport = open_transport(address, serve_params=False)
    sim_time = bool((running_params(transport) or {}).get("use_sim_time", False))
    graph = Graph(sim_time=sim_time, transport=transport, clock_hz=None)
    node = graph.create_node(f"belvedere_{kind}_{os.getpid()}")
    if sim_time:
        graph.follow_clock(node)
    join_ros_master(graph, address)
    tool = Tool(graph, transport, node)
    threading.Thread(target=tool._end_when_asked, name="belvedere-tool-watch", daemon=True).start()
    return tool


def join_graph(address: GraphAddress, *, seed: int = 0, alone: bool | None = None) -> Graph:
    """A graph on the running one: its parameters copied, in its time (following its
    ``/clock`` when it simulates time), as ROS nodes join a running master. Where nothing
    holds parameters (nothing runs, or only tools), a graph on the wall clock, as a tool's;
    with ``alone`` given, this process makes the graph instead, holding its parameters, in
    simulated time if ``alone`` is true, as roslaunch starts a roscore when none runs.
    ``seed``: the graph's randomness."""
    transport = open_transport(address, serve_params=False)
    remote = running_params(transport)
    if remote is None:
        if alone is None:
            graph = Graph(sim_time=False, seed=seed, transport=transport, clock_hz=None)
        else:
            transport.serve_params = True  # read when the graph attaches it, just below
            graph = Graph(sim_time=alone, seed=seed, transport=transport)
        join_ros_master(graph, address)
        return graph
    following = bool(remote.get("use_sim_time", False))
    graph = Graph(sim_time=following, seed=seed, transport=transport, clock_hz=None)
    graph.params.set("/", remote)
    if following:
        graph.follow_clock(graph.create_node(f"belvedere_clock_follower_{os.getpid()}"))
    join_ros_master(graph, address)
    return graph


def join_ros_master(graph: Graph, address: GraphAddress) -> None:
    """With ``--ros-master URI``: the graph joins that ROS 1 master too (its parameters
    copied in where the graph has none of that name), until it shuts down."""
    if address.ros_master is None:
        return
    from belvedere.ros1wire import join_master

    handle = join_master(graph, address.ros_master)
    graph.shutdown_hooks.append(handle.close)
    logger.info("ROS 1 master: %s (joined)", handle.uri)


def running_params(transport: ZenohTransport) -> dict[str, Any] | None:
    """The running graph's parameters; None when nothing else runs (this process listens)
    or nothing holds parameters (a graph of tools only, on the wall clock)."""
    if transport.role == "listen":
        return None
    try:
        remote: Any = transport.param_request({"op": "get", "name": "/"})
    except GraphError:
        return None
    return remote if isinstance(remote, dict) else {}


def holds_parameters(address: GraphAddress) -> bool:
    """Whether a graph runs at ``address`` and a process of it holds the parameters (a
    launch, a simulation, a script run alone: ROS's master), not only tools."""
    if not graph_running(address.endpoint, address.domain):
        return False
    transport = ZenohTransport(
        endpoint=address.endpoint,
        domain=address.domain,
        serve_params=False,
        role="connect",
    )
    try:
        return running_params(transport) is not None
    finally:
        transport.close()


def wait_for(condition: object, timeout: float, step: float = 0.05) -> bool:
    """Poll ``condition()`` until it holds or ``timeout`` seconds pass."""
    deadline = time.monotonic() + timeout
    while True:
        if condition():  # type: ignore[operator]
            return True
        if time.monotonic() >= deadline:
            return False
        time.sleep(step)


def wait_for_messages(
    arrived: threading.Semaphore,
    *,
    limit: int | None,
    timeout: float | None,
    nothing: BelvedereError,
) -> None:
    """Until ``limit`` messages have arrived (each releases ``arrived``; None: forever) or
    ``timeout`` seconds pass; ``nothing`` is raised when none came in that time."""
    start = time.monotonic()
    received = 0
    while limit is None or received < limit:
        left = None if timeout is None else timeout - (time.monotonic() - start)
        if left is not None and left <= 0:
            if received == 0:
                raise nothing
            break
        if arrived.acquire(timeout=min(left, 0.5) if left is not None else 0.5):
            received += 1
