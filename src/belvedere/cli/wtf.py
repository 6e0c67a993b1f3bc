"""``belvedere wtf`` — roswtf's online checks of the running graph, in its report's form."""

from __future__ import annotations

import argparse
import sys

from belvedere.cli._tool import add_graph_options, graph_address
from belvedere.runtime import check_graph, open_tool

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "wtf",
        parents=[common],
        help="what is wrong with the graph: unconnected topics, TF tree, /clock (roswtf)",
    )
    add_graph_options(p, hosts=False)  # roswtf's own --listen SECONDS
    p.add_argument(
        "--listen", type=float, default=1.0, metavar="SECONDS", help="hear transforms this long"
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    tool = open_tool(graph_address(args), "wtf")
    try:
        report = check_graph(tool, listen=args.listen)
    finally:
        tool.close()
    sys.stdout.write(report.text())
    return 1 if report.errors else 0
