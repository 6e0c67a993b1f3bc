"""``belvedere run PKG EXECUTABLE [args…]`` (rosrun), or ``belvedere run SCRIPT [args…]``.

An executable belvedere has (:mod:`belvedere.nodes`) runs in this process, as one node on
the graph; any other is looked for in the package as rosrun looks (the package's
``scripts/``, ``nodes/``, then anywhere below it) and runs as the user's script. ROS's
arguments work as with rosrun: ``from:=to`` remaps, ``_param:=value`` sets the node's
private parameter (a YAML value), ``__name:=`` and ``__ns:=`` rename and place it. ``xacro
xacro`` runs ``belvedere xacro``.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from belvedere.cli import hand_over
from belvedere.cli._args import add_viewer_options
from belvedere.cli._script import add_script_options
from belvedere.cli._session import session_options
from belvedere.cli._tool import add_graph_options
from belvedere.errors import BelvedereError
from belvedere.packages import PackageIndex, find_package_root
from belvedere.runtime import rosrun

__all__ = ["add_parser", "run"]

TOOLS = {
    ("xacro", "xacro"): "xacro",
    ("xacro", "xacro.py"): "xacro",
    ("rostopic", "rostopic"): "topic",
    ("rosservice", "rosservice"): "service",
    ("rosnode", "rosnode"): "node",
    ("rosparam", "rosparam"): "param",
    ("rosmsg", "rosmsg"): "msg",
    ("rosmsg", "rossrv"): "srv",
    ("roswtf", "roswtf"): "wtf",
    ("rostest", "rostest"): "test",
}
"""Executables that are belvedere verbs rather than nodes: ``rosrun rostopic rostopic list``
is ``belvedere topic list``, as ROS installs its tools in their packages too."""


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "run",
        parents=[common],
        help="run a package's executable, as rosrun",
        description="belvedere run [options] PKG EXECUTABLE [args…] or belvedere run "
        "[options] SCRIPT [args…]; from:=to remaps, _param:=value, __name:=NAME, __ns:=NS as "
        "with rosrun. belvedere's options come first: everything after the executable is "
        "its own. A Python script runs as python3 runs it (its __file__ an absolute path): "
        "beside a running graph, in this very process; with none, this provides one (the "
        "parameter server, as roscore) and runs the script beside it.",
    )
    p.add_argument("target", metavar="PKG|SCRIPT", help="a package, or a script's path")
    p.add_argument("words", nargs=argparse.REMAINDER, metavar="ARGS", help="the executable…")
    p.add_argument("--headless", action="store_true", help="no viewer (rviz)")
    p.add_argument("--seed", type=int, default=0, help="seed of the simulation's randomness")
    add_viewer_options(p)
    add_script_options(p)
    add_graph_options(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    target, words = args.target, list(args.words)
    script: Path | None = None
    typed: str | None = None
    if os.path.isfile(target):
        script, typed = Path(target), target
        root = find_package_root(script.resolve())
        package = root.name if root is not None else ""
        executable = script.name
    else:
        if not words:
            msg = f"belvedere run {target}: which executable? (run PKG EXECUTABLE [args])"
            raise BelvedereError(msg)
        package, executable, words = target, words[0], words[1:]
    if (package, executable) in TOOLS:
        from belvedere.cli import main

        # run's own --package-path reaches the tool (rostest finds its packages there)
        paths = [w for p in args.package_path or [] for w in ("--package-path", str(p))]
        return main([TOOLS[package, executable], *paths, *words])
    packages = PackageIndex.from_environment(
        package_path=args.package_path, near=script if script is not None else None
    )
    return rosrun(
        package,
        executable,
        words,
        packages,
        session_options(args),
        script=script,
        argv0=typed,
        take_over=hand_over,
    )
