"""``belvedere node list|info|ping|kill|machine|cleanup`` — rosnode, across processes.

There is no XML-RPC: ``ping`` times a round trip to the process that holds the node (on the
graph's Zenoh network), and ``kill`` asks that process to shut the node down."""

from __future__ import annotations

import argparse
import itertools
import sys
import time

from belvedere.cli._tool import action_parsers, graph_address
from belvedere.errors import BelvedereError
from belvedere.graph import GraphInfo
from belvedere.msgs import short
from belvedere.runtime import (
    Tool,
    kill_nodes,
    known_node,
    machines,
    open_tool,
    ping_node,
    unreachable_nodes,
)

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("node", parents=[common], help="list nodes and what they do")
    verb = action_parsers(p, common)
    verb("list", "running nodes")
    verb("info", "a node's topics and services").add_argument("node")
    v = verb("ping", "time a round trip to a node's process (until Ctrl-C, or -c times)")
    v.add_argument("node", nargs="?")
    v.add_argument("-a", "--all", action="store_true", help="ping every node")
    v.add_argument("-c", "--count", type=int, metavar="N", help="ping N times")
    v = verb("kill", "ask nodes to shut down (a rospy script runs its shutdown hooks)")
    v.add_argument("nodes", nargs="*")
    v.add_argument("-a", "--all", action="store_true", help="every node")
    verb("machine", "the machines nodes run on, or a machine's nodes").add_argument(
        "machine", nargs="?"
    )
    verb("cleanup", "list nodes whose process does not answer")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    tool = open_tool(graph_address(args), "node")
    try:
        info = tool.info()
        own = tool.node.full_name
        others = info.nodes - {own}
        if args.action == "list":
            _write(sorted(others))
        elif args.action == "info":
            sys.stdout.write(_info(info, known_node(info, args.node, besides=[own])))
        elif args.action == "ping":
            return _ping(tool, info, args)
        elif args.action == "kill":
            return _kill(tool, info, args)
        elif args.action == "machine":
            hosts = machines(info)
            if args.machine is None:
                _write(sorted(hosts))
            elif args.machine in hosts:
                _write(sorted(hosts[args.machine] - {own}))
            else:
                msg = f"no node runs on machine {args.machine!r}"
                raise BelvedereError(msg, hint=f"machines: {', '.join(sorted(hosts))}")
        else:
            return _cleanup(tool, info)
        return 0
    finally:
        tool.close()


def _write(lines: list[str]) -> None:
    sys.stdout.write("".join(line + "\n" for line in lines))


def _info(info: GraphInfo, name: str) -> str:
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
    return "\n".join(out)


def _ping(tool: Tool, info: GraphInfo, args: argparse.Namespace) -> int:
    own = tool.node.full_name
    if args.all:
        nodes, count = sorted(info.nodes - {own}), 1 if args.count is None else args.count
    elif args.node is None:
        msg = "node ping needs a node (or -a for every node)"
        raise BelvedereError(msg, hint="see 'belvedere node list'")
    else:
        nodes, count = [known_node(info, args.node, besides=[own])], args.count
    failed: list[str] = []
    for node in nodes:
        sys.stdout.write(f"node is [{node}]\npinging {node} with a timeout of 3.0s\n")
        for turn in itertools.count(1):
            pong = ping_node(tool, node)
            if pong is None:
                sys.stdout.write(f"ERROR: connection to [{node}]'s process timed out\n")
                failed.append(node)
                break
            sys.stdout.write(f"reply from {pong.process}\ttime={pong.ms:f}ms\n")
            sys.stdout.flush()
            if count is not None and turn >= count:
                break
            time.sleep(1.0)  # rosnode ping's pace
    if failed:
        _write(["ERROR: connection failed to:", *(f" * {node}" for node in failed)])
        return 1
    return 0


def _kill(tool: Tool, info: GraphInfo, args: argparse.Namespace) -> int:
    own = tool.node.full_name
    if args.all:
        nodes = sorted(info.nodes - {own})
    elif not args.nodes:
        msg = "node kill needs nodes (or -a for every node)"
        raise BelvedereError(msg, hint="see 'belvedere node list'")
    else:
        nodes = [known_node(info, node, besides=[own]) for node in args.nodes]
    _write([f"killing {node}" for node in nodes])
    left = kill_nodes(tool, nodes)
    if left:
        msg = f"did not shut down (their process does not answer): {', '.join(left)}"
        raise BelvedereError(msg, hint="see 'belvedere node cleanup'")
    _write(["killed"])
    return 0


def _cleanup(tool: Tool, info: GraphInfo) -> int:
    silent = unreachable_nodes(tool, info)
    if not silent:
        return 0
    _write(["Unable to contact the following nodes:", *(f" * {node}" for node in silent)])
    sys.stdout.write(
        "belvedere cannot unregister them: they leave the graph when their process ends "
        "(belvedere node kill, or end the process)\n"
    )
    return 1
