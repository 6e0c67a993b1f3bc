"""``belvedere display MODEL [name:=value …]``: the robot in the browser with joint sliders
(rviz + robot_state_publisher + joint_state_publisher_gui)."""

from __future__ import annotations

import argparse
import sys
import time
import webbrowser

from belvedere.cli._args import add_viewer_options, mappings_only
from belvedere.cli._foxglove import add_foxglove_options, bridge_options
from belvedere.cli._report import notice, report_diagnostics
from belvedere.cli._tool import add_graph_options, graph_address, serve_for
from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.runtime import join_ros_master, open_transport, start_bridge
from belvedere.tf import JointStatePublisher, RobotStatePublisher

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("display", parents=[common], help="show a robot model in the browser")
    p.add_argument("input", metavar="MODEL", help="URDF or xacro file")
    p.add_argument("--rviz", metavar="CONFIG", help="an rviz .rviz config to start from")
    add_viewer_options(p)
    p.add_argument("--open", action="store_true", help="open a browser on the viewer")
    add_foxglove_options(p)
    p.add_argument("--duration", type=float, help="exit after SECONDS (for scripts)")
    add_graph_options(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from belvedere.viewer import Viewer, read_rviz

    mappings = mappings_only(list(args.extra))
    packages = PackageIndex.from_environment(package_path=args.package_path, near=args.input)
    started = time.monotonic()
    model = RobotModel.from_path(args.input, mappings=mappings, packages=packages)
    report_diagnostics(model.warnings, source=args.input)
    graph = Graph(sim_time=False, transport=open_transport(graph_address(args)))
    join_ros_master(graph, graph_address(args))
    graph.params.set("/robot_description", model.to_urdf())
    RobotStatePublisher(graph.create_node("robot_state_publisher"), model)
    jsp = JointStatePublisher(graph.create_node("joint_state_publisher"), model)
    rviz = read_rviz(args.rviz) if args.rviz else None
    bridge = start_bridge(graph, bridge_options(args))
    try:
        viewer = Viewer(
            graph,
            model=model,
            host=args.host,
            port=args.port,
            allow_origins=args.allow_origins,
            rviz=rviz,
            rviz_path=args.rviz,
            joint_publisher=jsp,
            packages=packages,
        )
    except BaseException:
        if bridge is not None:
            bridge.close()
        raise
    graph.start(rtf=None)
    sys.stdout.write(f"{viewer.url}\n")
    sys.stdout.flush()
    notice(f"viewer ready in {time.monotonic() - started:.2f} s (Ctrl-C to stop)")
    if args.open:
        webbrowser.open(viewer.url)
    try:
        serve_for(args.duration)
    finally:
        if bridge is not None:
            bridge.close()
        viewer.close()
        graph.shutdown()
    return 0
