"""``belvedere foxglove [--port P]``: serve a running graph's topics to Foxglove
(foxglove_bridge, beside anything that runs)."""

from __future__ import annotations

import argparse
import os

from belvedere.cli._foxglove import (
    DEFAULT_PORT,
    HOST_HELP,
    add_origin_option,
    bridge_options,
    port,
)
from belvedere.cli._tool import add_graph_options, graph_address, serve_for
from belvedere.runtime import join_graph, start_bridge

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "foxglove",
        parents=[common],
        help="serve the graph's topics to Foxglove",
        description="Join the running graph and serve its topics over Foxglove's WebSocket "
        "protocol (open the printed ws:// URL in Foxglove).",
    )
    p.add_argument(
        "--port",
        type=port,
        default=DEFAULT_PORT,
        dest="foxglove",
        help=f"port to serve on (default: {DEFAULT_PORT}; 0: any free port)",
    )
    p.add_argument("--host", default="127.0.0.1", dest="foxglove_host", help=HOST_HELP)
    add_origin_option(p, "--allow-origin")
    p.add_argument("--duration", type=float, help="exit after SECONDS (for scripts)")
    add_graph_options(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    graph = join_graph(graph_address(args))
    try:
        bridge = start_bridge(
            graph, bridge_options(args), node_name=f"foxglove_bridge_{os.getpid()}"
        )
        assert bridge is not None
        graph.start(rtf=None)
        try:
            serve_for(args.duration)
        finally:
            bridge.close()
    finally:
        graph.shutdown()
    return 0
