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
import shlex
import subprocess
import time
from pathlib import Path
from typing import NoReturn

from belvedere.cli import hand_over
from belvedere.cli._args import add_viewer_options
from belvedere.cli._script import add_script_options
from belvedere.cli._tool import add_graph_options, holds_parameters
from belvedere.errors import BelvedereError, did_you_mean
from belvedere.graph import graph_running
from belvedere.mappings import split_ros_args
from belvedere.packages import PackageIndex, PackageNotFoundError, find_package_root
from belvedere.pyscripts import prepare_script

__all__ = ["add_parser", "run"]

TOOLS = {("xacro", "xacro"): "xacro", ("xacro", "xacro.py"): "xacro"}
"""Executables that are belvedere verbs rather than nodes."""


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

        return main([TOOLS[package, executable], *words])
    packages = PackageIndex.from_environment(
        package_path=args.package_path, near=script if script is not None else None
    )
    # A script gets its arguments as rosrun passes them (rospy reads its own remaps,
    # _param:= and __name:=). Like rosrun it joins the graph that runs (this process
    # imports no more than that needs); only when none does, this provides one as roscore
    # would (also where only tools run): the parameter server, in wall time.
    if script is not None and holds_parameters(args):
        return run_alone(script, words, packages, args, argv0=typed)
    from belvedere import nodes
    from belvedere.cli._session import run_session
    from belvedere.launch import LaunchConfig, LaunchNode
    from belvedere.launch._runtime import find_script

    if script is None and nodes.find(package, executable) is None:
        have = nodes.executables(package)
        try:
            home: Path | None = packages.find(package)
        except PackageNotFoundError:
            if not have:
                raise
            home = None  # a package belvedere has in itself (map_server, tf…)
        script = find_script(home, executable) if home is not None else None
        if script is None:
            dirs = [home / "scripts", home / "nodes"] if home is not None else []
            scripts = [p.name for d in dirs for p in d.glob("*")]
            msg = f"package {package!r} has no executable {executable!r}"
            hint = did_you_mean(executable, [*have, *scripts])
            raise BelvedereError(
                msg, hint=hint or f"belvedere has for {package}: {', '.join(have) or 'none'}"
            )
    plain, remaps, params, name, namespace = split_ros_args(words)
    if name is None:
        name = executable.removesuffix(".py")
        if nodes.anonymous(package, executable):
            name += f"_{time.time_ns()}"  # rosrun rviz rviz beside a launch's /rviz
    spec = LaunchNode(
        pkg=package,
        type=executable,
        name=name,
        namespace="/" + (namespace or "").strip("/"),
        args=shlex.join(plain),
        output="screen",
        required=True,
        remappings=tuple(remaps.items()),
    )
    config = LaunchConfig()
    if script is None:
        for key, value in params.items():
            config.set_param(f"{spec.full_name}/{key}", value, None)
        config.nodes.append(spec)
        # A client of the graph (map_saver…) joins the graph that runs, as a ROS node joins
        # the master; the rest (simulators) make the graph.
        join = nodes.joins_running_graph(package, executable) and graph_running(
            args.endpoint, args.domain
        )
        return run_session(config, packages, args, quiet_end=True, join=join)
    if holds_parameters(args):
        return run_alone(script, words, packages, args)
    return run_session(
        config, packages, args, script=(spec, script, words), sim_time=False, quiet_end=True
    )


def run_alone(
    script: Path,
    words: list[str],
    packages: PackageIndex,
    args: argparse.Namespace,
    *,
    argv0: str | None = None,
) -> int:
    """Run ``script`` on the graph that is running; its exit status is ours. In the
    ``belvedere`` command's own process, as ``python3 script.py`` runs it: one Python starts,
    not two, so the script is on the graph as soon as under ROS (``argv0``: the script as
    typed, its ``sys.argv[0]``; else the absolute path, as rosrun gives)."""
    ready = prepare_script(script, argv0=argv0)
    env = {"ROS_PACKAGE_PATH": os.pathsep.join(str(p) for p in packages.search_path)}
    if args.domain is not None:
        env["BELVEDERE_DOMAIN"] = str(args.domain)
    if args.endpoint:
        env["BELVEDERE_ENDPOINT"] = args.endpoint

    def take_over() -> NoReturn:
        os.environ.update(env)
        ready.run_here(words)

    if hand_over(take_over):
        return 0
    process = subprocess.Popen([*ready.command(), *words], env={**os.environ, **env})
    while True:
        try:
            return process.wait()
        except KeyboardInterrupt:
            continue  # the script got the Ctrl-C too: it ends in its own way
