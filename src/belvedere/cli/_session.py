"""Running a launch configuration until it ends: ``launch`` and ``run`` share this."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from belvedere.cli._script import ScriptOptions, install_script
from belvedere.cli._tool import open_transport
from belvedere.graph import Graph
from belvedere.launch import LaunchConfig, LaunchNode
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex

__all__ = ["run_session"]


def run_session(
    config: LaunchConfig,
    packages: PackageIndex,
    args: argparse.Namespace,
    *,
    script: tuple[LaunchNode, Path, list[str]] | None = None,
    sim_time: bool = True,
) -> int:
    """Start everything ``config`` asks for on one graph (and ``script``: a user's script
    run as that node, with those arguments) and run until Ctrl-C, ``--duration``, or a
    required node exits. ``sim_time``: the graph's time is simulated (``/clock``,
    ``/use_sim_time``), else the wall clock's, as with a bare roscore."""
    graph = Graph(sim_time=sim_time, seed=args.seed, transport=open_transport(args))
    runtime = LaunchRuntime(
        config,
        graph,
        packages,
        headless=args.headless,
        viewer_options={
            "host": args.host,
            "port": args.port,
            "allow_origins": args.allow_origins,
        },
    )
    try:
        runtime.start()
        if script is not None and not runtime.run_script(script[0], script[1], argv=script[2]):
            return 1
        install_script(graph, ScriptOptions.from_args(args))
        _run(graph, runtime, args)
    except KeyboardInterrupt:
        pass
    finally:
        sys.stdout.flush()
        runtime.close()
        graph.shutdown()
    return 0


def _run(graph: Graph, runtime: LaunchRuntime, args: argparse.Namespace) -> None:
    started = time.monotonic()
    last_check = [0.0]

    def required_exited() -> bool:
        now = time.monotonic()
        if now - last_check[0] < 0.2:
            return False
        last_check[0] = now
        spec = runtime.poll_processes()
        if spec is not None:
            sys.stderr.write(f"required node {spec.full_name} exited: shutting down\n")
            return True
        return False

    if not graph.sim_time:
        # In wall time nothing else may be scheduled: wake up to look at the processes.
        graph.create_node("belvedere_run").timer(0.2, lambda: None)
    graph.run(duration=args.duration, rtf=args.rtf, until=required_exited)
    if args.duration is not None:
        wall = time.monotonic() - started
        sys.stderr.write(f"simulated {args.duration:g} s in {wall:.3f} s\n")
