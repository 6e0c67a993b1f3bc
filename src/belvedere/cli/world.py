"""``belvedere world save PATH``: save the running simulation's world (Gazebo's File > Save
World As) from another terminal.

Joins the running graph and calls the simulation's ``/gazebo/save_world`` service; the
simulation writes the file (atomically, while it runs on) and the path written is printed on
stdout. A relative PATH is relative to this command's directory, not the simulation's.
"""

from __future__ import annotations

import argparse
import os
import sys

from belvedere.cli._tool import action_parsers, graph_address
from belvedere.errors import BelvedereError
from belvedere.runtime import open_tool
from belvedere.sim import SAVE_WORLD, SAVE_WORLD_TYPE

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("world", parents=[common], help="the running simulation's world")
    action = action_parsers(p, common)
    save = action("save", "write the simulated world, as it is now, to a .world file")
    save.add_argument("path", metavar="PATH", help="the .world file to write (SDF 1.6)")
    save.add_argument(
        "--timeout",
        type=float,
        default=60.0,
        metavar="SECONDS",
        help="how long to wait for the simulation (default 60)",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    path = os.path.abspath(os.path.expanduser(args.path))
    tool = open_tool(graph_address(args), "world")
    try:
        offered = tool.info().services.get(SAVE_WORLD)
        if not offered:
            msg = f"no simulation is running on this graph ({SAVE_WORLD} is not offered)"
            raise BelvedereError(
                msg,
                hint="start one with 'belvedere sim … --engine physics' or a Gazebo launch "
                "file; --domain/--endpoint choose the graph",
            )
        tool.graph.start(rtf=None)
        response = tool.node.call_service(
            SAVE_WORLD, SAVE_WORLD_TYPE, {"path": path}, timeout=args.timeout
        )
    finally:
        tool.close()
    if not response.success:
        raise BelvedereError(response.status_message.removeprefix("SaveWorld: "))
    sys.stdout.write(f"{response.path}\n")
    return 0
