"""Hosting an executable as rosrun does: one of belvedere's nodes in this process, or the
user's script, beside the graph that runs or on one this process provides (as roscore).

A script gets its arguments as rosrun passes them (rospy reads its own remaps, ``_param:=``
and ``__name:=``). Like rosrun it joins the graph that runs, in the hosting process itself
when the caller can hand its process over (:data:`HandOver`), else in a child; only when
none runs, the host provides one as roscore would (also where only tools run): the
parameter server, in wall time.
"""

from __future__ import annotations

import os
import shlex
import subprocess
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, NoReturn

from belvedere.errors import BelvedereError, did_you_mean
from belvedere.graph import graph_running
from belvedere.mappings import split_ros_args
from belvedere.runtime._join import GraphAddress, holds_parameters
from belvedere.runtime._session import SessionOptions, run_session

if TYPE_CHECKING:
    from belvedere.packages import PackageIndex

__all__ = ["HandOver", "rosrun", "run_alone"]

HandOver = Callable[[Callable[[], NoReturn]], bool]
"""How the caller gives its process to a script: called with what takes the process over
once the caller is done, true if it will (``belvedere``'s command line can; a test or a
program calling in-process cannot)."""


def rosrun(
    package: str,
    executable: str,
    words: list[str],
    packages: PackageIndex,
    options: SessionOptions,
    *,
    script: Path | None = None,
    argv0: str | None = None,
    take_over: HandOver | None = None,
) -> int:
    """Run ``executable`` of ``package`` with rosrun's arguments ``words`` until it ends; its
    exit status. ``script``: the user's script, given by its path (``argv0``: as typed), in
    place of a lookup in ``package``. ``take_over``: see :data:`HandOver`."""
    address = options.address
    # (this process imports no more than a script beside a running graph needs)
    if script is not None and holds_parameters(address):
        _refuse_run_options(options)
        return run_alone(script, words, packages, address, argv0=argv0, take_over=take_over)
    from belvedere import nodes
    from belvedere.launch import LaunchConfig, LaunchNode
    from belvedere.launch._runtime import find_script
    from belvedere.packages import PackageNotFoundError

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
        name = nodes.node_name(package, executable)
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
            address.endpoint, address.domain
        )
        return run_session(config, packages, options, quiet_end=True, join=join)
    if holds_parameters(address):
        _refuse_run_options(options)
        return run_alone(script, words, packages, address, take_over=take_over)
    return run_session(
        config, packages, options, script=(spec, script, words), sim_time=False, quiet_end=True
    )


def _refuse_run_options(options: SessionOptions) -> None:
    """A script joining a running graph runs as ``python3 script.py`` would, in that graph's
    time: the options that shape a run of its own would be ignored, so they are refused."""
    given = [
        word
        for word, used in (
            ("--pub", bool(options.pubs)),
            ("--echo", bool(options.echoes)),
            ("--duration", options.duration is not None),
            ("--rtf", options.rtf != 1.0),
        )
        if used
    ]
    if given:
        msg = (
            f"{', '.join(given)}: a script run beside a running graph keeps that graph's time "
            "and runs until it ends"
        )
        hint = "use 'belvedere topic pub' or 'belvedere topic echo' in another terminal"
        raise BelvedereError(msg, hint=hint)


def run_alone(
    script: Path,
    words: list[str],
    packages: PackageIndex,
    address: GraphAddress,
    *,
    argv0: str | None = None,
    take_over: HandOver | None = None,
) -> int:
    """Run ``script`` on the graph that is running at ``address``; its exit status is ours.
    In the caller's own process when ``take_over`` takes it, as ``python3 script.py`` runs
    it: one Python starts, not two, so the script is on the graph as soon as under ROS
    (``argv0``: the script as typed, its ``sys.argv[0]``; else the absolute path, as rosrun
    gives); else in a child process."""
    from belvedere.pyscripts import prepare_script

    ready = prepare_script(script, argv0=argv0)
    env = {"ROS_PACKAGE_PATH": os.pathsep.join(str(p) for p in packages.search_path)}
    if address.domain is not None:
        env["BELVEDERE_DOMAIN"] = str(address.domain)
    if address.endpoint:
        env["BELVEDERE_ENDPOINT"] = address.endpoint

    def here() -> NoReturn:
        os.environ.update(env)
        ready.run_here(words)

    if take_over is not None and take_over(here):
        return 0
    process = subprocess.Popen([*ready.command(), *words], env={**os.environ, **env})
    while True:
        try:
            return process.wait()
        except KeyboardInterrupt:
            continue  # the script got the Ctrl-C too: it ends in its own way
