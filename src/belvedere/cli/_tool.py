"""What the graph tools share: a small graph of their own, joined to the others by Zenoh."""

from __future__ import annotations

import argparse
import logging
import os
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph import (
    MAX_DOMAIN,
    Graph,
    GraphError,
    GraphInfo,
    Node,
    TransportError,
    ZenohTransport,
    check_domain,
    graph_running,
)

__all__ = [
    "USE_SIM_TIME",
    "Tool",
    "action_parsers",
    "add_graph_options",
    "holds_parameters",
    "join_graph",
    "open_clock_transport",
    "open_tool",
    "open_transport",
    "refuse_second_clock",
    "wait_for",
]

logger = logging.getLogger("belvedere.cli")

USE_SIM_TIME = "/use_sim_time"
CLOCK = "/clock"


def _domain(text: str) -> int:
    try:
        return check_domain(text)
    except TransportError as err:
        raise argparse.ArgumentTypeError(err.message) from None


def add_graph_options(p: argparse.ArgumentParser) -> None:
    """``--domain`` and ``--endpoint``: which graph to join."""
    p.add_argument(
        "--domain",
        type=_domain,
        metavar="N",
        help=f"the graph to join, 0 to {MAX_DOMAIN} (default: BELVEDERE_DOMAIN or 0); "
        "domain N meets on tcp/127.0.0.1:<7450+N>",
    )
    p.add_argument(
        "--endpoint",
        metavar="ENDPOINT",
        help="Zenoh endpoint of the graph (default: BELVEDERE_ENDPOINT, else the domain's)",
    )


def open_transport(args: argparse.Namespace, **options: Any) -> ZenohTransport:
    """Join the graph that ``--domain``/``--endpoint`` name, and say which (one line on
    stderr; ``-q`` hides it)."""
    transport = ZenohTransport(
        endpoint=getattr(args, "endpoint", None), domain=getattr(args, "domain", None), **options
    )
    how = "listening" if transport.role == "listen" else "connected"
    logger.info("graph: domain %d (%s, %s)", transport.domain, transport.endpoint, how)
    return transport


def open_clock_transport(
    args: argparse.Namespace, *, clock: bool = True, **options: Any
) -> ZenohTransport:
    """:func:`open_transport` for a process that will publish ``/clock`` (when ``clock``):
    refused, and closed, where another process already does (:func:`refuse_second_clock`)."""
    transport = open_transport(args, **options)
    if clock:
        try:
            refuse_second_clock(transport)
        except BelvedereError:
            transport.close()
            raise
    return transport


def action_parsers(
    parser: argparse.ArgumentParser, common: argparse.ArgumentParser
) -> Callable[[str, str], argparse.ArgumentParser]:
    """A maker of ``belvedere VERB ACTION`` sub-parsers, each with the common options,
    ``--domain`` and ``--endpoint``."""
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)

    def action(name: str, help_text: str) -> argparse.ArgumentParser:
        sub = actions.add_parser(name, parents=[common], help=help_text)
        add_graph_options(sub)
        return sub

    return action


@dataclass
class Tool:
    graph: Graph
    transport: ZenohTransport
    node: Node

    def info(self, timeout: float = 0.5) -> GraphInfo:
        return self.transport.info(timeout=timeout)

    def wait_for_clock(self, timeout: float = 2.0) -> None:
        """In a simulation's time, until its ``/clock`` has been heard (the graph's time
        reads 0 before: a stamp of "now" would be 0). The executor must be running."""
        if self.graph.executor.following:
            wait_for(lambda: self.graph.now_ns() > 0, timeout, step=0.01)

    def close(self) -> None:
        self.graph.shutdown()


def open_tool(args: argparse.Namespace, kind: str) -> Tool:
    """A graph with one anonymous node, connected (or listening) on the endpoint, in the
    running graph's time (following its ``/clock`` when it simulates time, as rostopic and
    tf_echo do under ``/use_sim_time``), else the wall clock's."""
    transport = open_transport(args, serve_params=False)
    sim_time = bool((_running_params(transport) or {}).get("use_sim_time", False))
    graph = Graph(sim_time=sim_time, transport=transport, clock_hz=None)
    node = graph.create_node(f"belvedere_{kind}_{os.getpid()}")
    if sim_time:
        graph.follow_clock(node)
    return Tool(graph, transport, node)


def join_graph(args: argparse.Namespace, *, alone: bool | None = None) -> Graph:
    """A graph on the running one: its parameters copied, in its time (following its
    ``/clock`` when it simulates time), as ROS nodes join a running master. Where nothing
    holds parameters (nothing runs, or only tools), a graph on the wall clock, as a tool's;
    with ``alone`` given, this process makes the graph instead, holding its parameters, in
    simulated time if ``alone`` is true, as roslaunch starts a roscore when none runs."""
    transport = open_transport(args, serve_params=False)
    seed = getattr(args, "seed", 0)
    remote = _running_params(transport)
    if remote is None:
        if alone is None:
            return Graph(sim_time=False, seed=seed, transport=transport, clock_hz=None)
        transport.serve_params = True  # read when the graph attaches it, just below
        return Graph(sim_time=alone, seed=seed, transport=transport)
    following = bool(remote.get("use_sim_time", False))
    graph = Graph(sim_time=following, seed=seed, transport=transport, clock_hz=None)
    graph.params.set("/", remote)
    if following:
        graph.follow_clock(graph.create_node(f"belvedere_clock_follower_{os.getpid()}"))
    return graph


def _running_params(transport: ZenohTransport) -> dict[str, Any] | None:
    """The running graph's parameters; None when nothing else runs (this process listens)
    or nothing holds parameters (a graph of tools only, on the wall clock)."""
    if transport.role == "listen":
        return None
    try:
        remote: Any = transport.param_request({"op": "get", "name": "/"})
    except GraphError:
        return None
    return remote if isinstance(remote, dict) else {}


def holds_parameters(args: argparse.Namespace) -> bool:
    """Whether a graph runs on the endpoint and a process of it holds the parameters (a
    launch, a simulation, a script run alone: ROS's master), not only tools."""
    if not graph_running(getattr(args, "endpoint", None), getattr(args, "domain", None)):
        return False
    transport = ZenohTransport(
        endpoint=getattr(args, "endpoint", None),
        domain=getattr(args, "domain", None),
        serve_params=False,
        role="connect",
    )
    try:
        return _running_params(transport) is not None
    finally:
        transport.close()


def refuse_second_clock(transport: ZenohTransport) -> None:
    """A simulation starting where another process already publishes ``/clock`` is an
    error naming that process: a graph has one clock (ROS 1 one master, and Gazebo refuses
    a second server on it); two would make ``/clock`` jump between their times."""
    if transport.role == "listen":
        return  # nothing else runs here
    info = transport.info(timeout=1.0)
    owners = sorted(
        {
            process
            for _, node in info.publishers.get(CLOCK, set())
            for process in info.processes.get(node, {node})
        }
    )
    if owners:
        msg = (
            f"a simulation already runs on this graph: {', '.join(owners)} publishes {CLOCK}, "
            "and a graph has one clock"
        )
        raise BelvedereError(
            msg,
            hint="stop it first (Ctrl-C in its terminal), or run this one on a graph of its "
            "own (--domain N)",
        )
    remote = _running_params(transport)
    if remote is not None and not remote.get("use_sim_time", False):
        logger.warning(
            "warning: this graph already runs on the wall clock (the process that started it "
            "holds its parameters, /use_sim_time false): the processes that joined it keep "
            "the wall clock, not this simulated time; start the simulation first, or on a "
            "graph of its own (--domain N)"
        )


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
