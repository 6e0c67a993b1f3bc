"""What the graph tools share: a small graph of their own, joined to the others by Zenoh."""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable
from dataclasses import dataclass

from belvedere.graph import Graph, GraphInfo, Node, ZenohTransport

__all__ = ["Tool", "action_parsers", "add_endpoint_option", "open_tool", "wait_for"]


def add_endpoint_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--endpoint",
        metavar="ENDPOINT",
        help="Zenoh endpoint of the graph (default: BELVEDERE_ENDPOINT or tcp/127.0.0.1:7450)",
    )


def action_parsers(
    parser: argparse.ArgumentParser, common: argparse.ArgumentParser
) -> Callable[[str, str], argparse.ArgumentParser]:
    """A maker of ``belvedere VERB ACTION`` sub-parsers, each with the common options and
    ``--endpoint``."""
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)

    def action(name: str, help_text: str) -> argparse.ArgumentParser:
        sub = actions.add_parser(name, parents=[common], help=help_text)
        add_endpoint_option(sub)
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
    transport = ZenohTransport(endpoint=getattr(args, "endpoint", None), serve_params=False)
    graph = Graph(sim_time=False, transport=transport)
    node = graph.create_node(f"belvedere_{kind}_{os.getpid()}")
    return Tool(graph, transport, node)


def wait_for(condition: object, timeout: float, step: float = 0.05) -> bool:
    """Poll ``condition()`` until it holds or ``timeout`` seconds pass."""
    deadline = time.monotonic() + timeout
    while True:
        if condition():  # type: ignore[operator]
            return True
        if time.monotonic() >= deadline:
            return False
        time.sleep(step)
