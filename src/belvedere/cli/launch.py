"""``belvedere launch PKG FILE.launch [arg:=value …]`` (or ``PATH.launch``): roslaunch, with
every node in this process on one graph."""

from __future__ import annotations

import argparse
import logging
import os
import sys
from pathlib import Path

from belvedere import nodes
from belvedere.cli._args import add_viewer_options, mappings_only
from belvedere.cli._foxglove import add_foxglove_options
from belvedere.cli._report import report_lines
from belvedere.cli._script import add_script_options, script_options
from belvedere.cli._session import session_options
from belvedere.cli._tool import add_graph_options
from belvedere.errors import BelvedereError, did_you_mean
from belvedere.launch import LaunchConfig, LaunchError, load_launch
from belvedere.launch._listing import (
    dump_params,
    file_list,
    find_executable,
    node_command,
    node_list,
    summary,
)
from belvedere.packages import PackageIndex
from belvedere.runtime import run_launch

__all__ = ["add_parser", "run"]

logger = logging.getLogger("belvedere.cli")


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "launch",
        parents=[common],
        help="run a roslaunch file",
        description="Run a ROS launch file: belvedere launch PKG FILE.launch [name:=value …] "
        "or belvedere launch PATH.launch [name:=value …]. A launch that makes the graph "
        "simulates time: it publishes /clock (paced by --rtf) and /use_sim_time is true "
        "before any node starts. A launch of clients only (move_base, amcl, map_server, "
        "rviz, scripts …) beside a running graph joins it and follows its time; a second "
        "simulation on one graph is refused. Nodes live and die as roslaunch's "
        "processes: one that fails dies alone ('[name-N] process has died …', its log under "
        'ROS_LOG_DIR or ~/.ros/log), required="true" ends the launch, respawn="true" '
        "starts it again after respawn_delay; the exit status is 0, as roslaunch's.",
    )
    p.add_argument("target", metavar="PKG|PATH", help="a package name, or a launch file")
    p.add_argument("file", nargs="?", metavar="FILE", help="the launch file in PKG")
    p.add_argument("--dump-params", action="store_true", help="print the parameters and exit")
    p.add_argument("--nodes", action="store_true", help="print the node names and exit")
    p.add_argument("--args", metavar="NODE", dest="node_args", help="print a node's command")
    p.add_argument(
        "--files",
        action="store_true",
        help="print every file it reads (launch, xacro, yaml, rviz, world, map…), each with "
        "its kind, and exit",
    )
    p.add_argument("--headless", action="store_true", help="no viewer (rviz, gzclient)")
    p.add_argument("--seed", type=int, default=0, help="seed of the simulation's randomness")
    add_viewer_options(p)
    add_foxglove_options(p)
    add_script_options(p)
    add_graph_options(p)
    p.set_defaults(run=run)


def _launch_file(args: argparse.Namespace, packages: PackageIndex) -> Path:
    extra = list(args.extra)
    if args.file is not None and ":=" in args.file:
        extra.insert(0, args.file)
        args.file = None
    args.extra = extra
    if args.file is None:
        path = Path(args.target)
        if not os.path.exists(path) or os.path.isdir(path):  # a FIFO…: the loader says why
            msg = f"launch file {args.target!r} does not exist"
            near = did_you_mean(path.name, (p.name for p in _launch_files(path.parent)))
            hint = near or "or give a package and a file: launch PKG FILE"
            raise BelvedereError(msg, hint=hint)
        return path
    root = packages.find(args.target)
    direct: Path = root / str(args.file)
    if os.path.isfile(direct):
        return direct
    found = sorted(p for p in root.rglob(Path(args.file).name) if os.path.isfile(p))
    if not found:
        msg = f"no launch file {args.file!r} in package {args.target!r} ({root})"
        launches = _launch_files(root, everywhere=True)
        names = sorted({p.name for p in launches})
        near = did_you_mean(Path(args.file).name, names)
        raise BelvedereError(
            msg, hint=near or f"the package's launch files: {', '.join(names) or 'none'}"
        )
    first: Path = found[0]
    return first


def _launch_files(directory: Path, *, everywhere: bool = False) -> list[Path]:
    """The launch files in ``directory`` (and below it, ``everywhere``)."""
    if not directory.is_dir():
        return []
    pattern = "*.launch*" if not everywhere else "**/*.launch*"
    return [p for p in directory.glob(pattern) if p.is_file()]


def run(args: argparse.Namespace) -> int:
    packages = PackageIndex.from_environment(
        package_path=args.package_path, near=args.target if os.path.exists(args.target) else None
    )
    path = _launch_file(args, packages)
    packages = packages.with_workspace_of(path)
    mappings = mappings_only(list(args.extra))
    script_options(args)  # bad --pub/--echo fail before anything starts
    config = load_launch(path, args=mappings, packages=packages)
    report_lines(config.warnings)
    if args.dump_params:
        sys.stdout.write(dump_params(config))
        return 0
    if args.nodes:
        sys.stdout.write(node_list(config))
        return 0
    if args.files:
        sys.stdout.write(file_list(config))
        return 0
    if args.node_args:
        sys.stdout.write(_node_args(config, args.node_args, packages) + "\n")
        return 0
    logger.info("%s", summary(config).rstrip("\n") + "\n")
    return run_launch(config, packages, session_options(args))


def _node_args(config: LaunchConfig, name: str, packages: PackageIndex) -> str:
    """roslaunch's ``--args NODE`` line; a node with no executable in its package (one that
    belvedere runs in process, or cannot run) shows as ``PKG/TYPE`` in its place."""
    spec = config.node(name)
    if spec is None:
        listed = ", ".join(n.full_name for n in [*config.nodes, *config.tests]) or "none"
        msg = f"no node {name!r} in this launch (nodes: {listed})"
        raise LaunchError(msg, hint="see --nodes")
    try:
        executable = find_executable(packages.find(spec.pkg, requested_at=spec.source), spec.type)
    except BelvedereError:
        executable = None
    if executable is None:
        how = (
            "belvedere runs it in process"
            if nodes.find(spec.pkg, spec.type) is not None
            else ("belvedere has no such node yet")
        )
        sys.stderr.write(
            f"{spec.source}: note: no executable {spec.type!r} in package {spec.pkg!r}: {how}\n"
        )
    return node_command(spec, str(executable or f"{spec.pkg}/{spec.type}"))
