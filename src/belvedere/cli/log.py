"""``belvedere log`` — the nodes' log messages from ``/rosout``, one a line: ``rosconsole
echo``, the terminal's rqt_console."""

from __future__ import annotations

import argparse
import logging
import sys
import threading
from typing import Any, Final

from belvedere.cli._tool import add_graph_options, graph_address
from belvedere.errors import BelvedereError
from belvedere.graph import did_you_mean, resolve_name
from belvedere.graph._log import LEVEL_NAMES
from belvedere.runtime import Tool, open_tool, wait_for_messages

__all__ = ["add_parser", "format_log", "run"]

logger = logging.getLogger("belvedere.cli")

LEVELS: Final = {name.lower(): level for level, name in LEVEL_NAMES.items()}
_COLORS: Final = {1: 92, 2: 97, 4: 93, 8: 91, 16: 95}
"""rosconsole echo's colours by level (light green, white, yellow, red, magenta)."""


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "log",
        parents=[common],
        help="print the nodes' log messages (/rosout)",
        description="Print what the nodes log (/rosout), one line a message: level, node, "
        "time, text (-v: with the function, file and line). Ctrl-C stops.",
    )
    p.add_argument(
        "--level",
        choices=list(LEVELS),
        default="debug",
        help="the least severe level shown (default: debug, everything the nodes publish)",
    )
    p.add_argument(
        "--node",
        action="append",
        default=[],
        metavar="NAME",
        help="only this node's messages (again for more nodes)",
    )
    p.add_argument("-n", dest="count", type=int, help="stop after COUNT messages")
    p.add_argument("--timeout", type=float, help="give up after SECONDS")
    add_graph_options(p)
    p.set_defaults(run=run)


def format_log(msg: Any, *, verbose: bool = False, color: bool = False) -> str:
    """One ``rosgraph_msgs/Log`` as ``[ LEVEL ] [node] [secs.usecs]: text`` (rosconsole
    echo's line, with the message's time); ``verbose`` adds where it was logged."""
    name = LEVEL_NAMES.get(msg.level, str(msg.level)).ljust(5)
    node = msg.name
    if color:
        name = f"\033[{_COLORS.get(msg.level, 0)}m{name}\033[0m"
        node = f"\033[1m{node}\033[0m"
    stamp = f"{msg.header.stamp.sec}.{msg.header.stamp.nanosec // 1000:06d}"
    line = f"[ {name} ] [{node}] [{stamp}]: {msg.msg}"
    if verbose:
        line += f"\n          [{msg.function}] {msg.file}:{msg.line}"
    return line


def run(args: argparse.Namespace) -> int:
    least = LEVELS[args.level]
    nodes = {resolve_name(n) for n in args.node}
    tool = open_tool(graph_address(args), "log")
    try:
        tool.graph.start(rtf=None)
        shown = threading.Semaphore(0)
        count = [0]
        color = sys.stdout.isatty()

        def show(msg: Any) -> None:
            if msg.level < least or (nodes and msg.name not in nodes):
                return
            if args.count is not None and count[0] >= args.count:
                return
            count[0] += 1
            sys.stdout.write(format_log(msg, verbose=args.verbose > 0, color=color) + "\n")
            sys.stdout.flush()
            shown.release()

        tool.node.subscribe("/rosout", "rosgraph_msgs/Log", show, queue_size=1000)
        if nodes:
            _name_absent(tool, nodes)
        return _wait(shown, args.count, args.timeout)
    finally:
        tool.close()


def _name_absent(tool: Tool, nodes: set[str]) -> None:
    """One warning per ``--node`` no node on the graph has (yet), with the names close to it."""
    present = tool.info().nodes - {tool.node.full_name}
    for name in sorted(nodes - present):
        close = did_you_mean(name, present)
        logger.warning("no node %s on the graph (yet)%s", name, f"; {close}" if close else "")


def _wait(shown: threading.Semaphore, count: int | None, timeout: float | None) -> int:
    """Until ``count`` messages are shown (forever: None), or ``timeout`` seconds pass."""
    nothing = f"no log message within {timeout or 0:g} s"
    wait_for_messages(
        shown,
        limit=count,
        timeout=timeout,
        nothing=BelvedereError(nothing, hint="is a node running and logging?"),
    )
    return 0
