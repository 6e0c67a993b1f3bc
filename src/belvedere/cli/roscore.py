"""``belvedere roscore [-p PORT]``: a ROS 1 master for the graph, so that real ROS 1 programs
(rostopic, rosparam, rospy and roscpp nodes, rosbag, rviz) and belvedere's nodes meet."""

from __future__ import annotations

import argparse
import ipaddress
import logging
import sys
import uuid

from belvedere.cli._tool import add_graph_options, graph_address, serve_for
from belvedere.errors import BelvedereError
from belvedere.ros1wire import DEFAULT_PORT, start_master
from belvedere.runtime import join_graph

__all__ = ["add_parser", "run"]

logger = logging.getLogger("belvedere.cli")


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "roscore",
        parents=[common],
        help="a ROS 1 master for the graph (real ROS 1 programs join it)",
        description="Serve ROS 1's master (the Master and Parameter Server APIs) for the "
        "graph: ROS 1 programs with ROS_MASTER_URI set to the printed URI see belvedere's "
        "nodes, topics, services and parameters as theirs, and belvedere sees theirs.",
    )
    p.add_argument(
        "-p",
        "--port",
        type=int,
        default=DEFAULT_PORT,
        help=f"the master's port (default: {DEFAULT_PORT}; 0: any free port)",
    )
    p.add_argument(
        "--host",
        default="127.0.0.1",
        help="the address to serve on (default: 127.0.0.1, this machine only); ROS 1's "
        "protocol has no authentication: anyone who reaches the port can do anything",
    )
    p.add_argument("--duration", type=float, help="exit after SECONDS (for scripts)")
    add_graph_options(p, ros_master=False)
    p.set_defaults(run=run)


def _loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def run(args: argparse.Namespace) -> int:
    graph = join_graph(graph_address(args), alone=False)
    try:
        try:
            handle = start_master(graph, args.host, args.port)
        except OSError as err:
            msg = (
                f"cannot serve a master on {args.host}:{args.port}: {err.strerror or err} "
                "(is another roscore running? `-p PORT` chooses another port)"
            )
            raise BelvedereError(msg) from None
        if not graph.params.has("/run_id"):
            graph.params.set("/run_id", str(uuid.uuid1()))
        graph.start(rtf=None)
        if not _loopback(args.host):
            logger.warning(
                "serving the ROS 1 master beyond this machine on %s: ROS 1's protocol has "
                "no authentication — anyone who can reach it can read and change the graph",
                args.host,
            )
        sys.stdout.write(f"ROS_MASTER_URI={handle.uri}\n")
        sys.stdout.flush()
        try:
            serve_for(args.duration)
        finally:
            handle.close()
    finally:
        graph.shutdown()
    return 0
