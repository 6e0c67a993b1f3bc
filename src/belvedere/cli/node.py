"""``belvedere node list|info`` — rosnode, across processes."""

from __future__ import annotations

import argparse
import sys

from belvedere.cli._tool import action_parsers, graph_address
from belvedere.errors import BelvedereError
from belvedere.graph import did_you_mean, resolve_name
from belvedere.msgs import short
from belvedere.runtime import open_tool

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("node", parents=[common], help="list nodes and what they do")
    verb = action_parsers(p, common)
    verb("list", "running nodes")
    verb("info", "a node's topics and services").add_argument("node")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    tool = open_tool(graph_address(args), "node")
    try:
        info = tool.info()
        own = tool.node.full_name
        if args.action == "list":
            for name in sorted(info.nodes - {own}):
                sys.stdout.write(name + "\n")
            return 0
        name = resolve_name(args.node)
        if name not in info.nodes:
            msg = f"unknown node {name}"
            hint = did_you_mean(name, info.nodes - {own}) or "see 'belvedere node list'"
            raise BelvedereError(msg, hint=hint)

        def section(title: str, table: dict[str, set[tuple[str, str]]]) -> list[str]:
            rows = [
                f" * {topic} [{short(typ)}]"
                for topic, entries in sorted(table.items())
                for typ, node in sorted(entries)
                if node == name
            ]
            return [title, *(rows or [" None"]), ""]

        out = [f"Node [{name}]"]
        out += section("Publications: ", info.publishers)
        out += section("Subscriptions: ", info.subscribers)
        out += section("Services: ", info.services)
        out += [f"Process: {process}" for process in sorted(info.processes.get(name, ()))]
        out.append("")
        sys.stdout.write("\n".join(out))
        return 0
    finally:
        tool.close()
