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
)

__all__ = [
    "Tool",
    "action_parsers",
    "add_graph_options",
    "join_graph",
    "open_tool",
    "open_transport",
    "wait_for",
]

logger = logging.getLogger("belvedere.cli")


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

    def close(self) -> None:
        self.graph.shutdown()


def open_tool(args: argparse.Namespace, kind: str) -> Tool:
    """A wall-time graph with one anonymous node, connected (or listening) on the endpoint."""
    transport = open_transport(args, serve_params=False)
    graph = Graph(sim_time=False, transport=transport)
    node = graph.create_node(f"belvedere_{kind}_{os.getpid()}")
    return Tool(graph, transport, node)


def join_graph(args: argparse.Namespace) -> Graph:
    """A graph on the running one: its parameters copied, in its time (following its
    ``/clock`` when it simulates time), as ROS nodes join a running master."""
    transport = open_transport(args, serve_params=False)
    try:
        remote: Any = transport.param_request({"op": "get", "name": "/"})
    except GraphError:
        remote = {}  # a graph without a parameter server (a tool's): nothing to copy
    if not isinstance(remote, dict):
        remote = {}
    sim_time = bool(remote.get("use_sim_time", False))
    seed = getattr(args, "seed", 0)
    graph = Graph(sim_time=sim_time, seed=seed, transport=transport, clock_hz=None)
    if remote:
        graph.params.set("/", remote)
    if sim_time:
        graph.follow_clock(graph.create_node(f"belvedere_clock_follower_{os.getpid()}"))
    return graph


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
