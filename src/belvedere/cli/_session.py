"""Running a launch configuration until it ends: ``launch`` and ``run`` share this."""

from __future__ import annotations

import argparse
import logging
import os
import sys
import threading
import time
from pathlib import Path

from belvedere.cli._foxglove import start_foxglove
from belvedere.cli._script import ScriptOptions, install_script
from belvedere.cli._tool import USE_SIM_TIME, join_graph, open_clock_transport
from belvedere.graph import Graph, GraphError
from belvedere.launch import LaunchConfig, LaunchNode
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex

__all__ = ["run_session"]

logger = logging.getLogger("belvedere.cli")

PROCESS_POLL_S = 0.2
"""How often subprocesses are looked at (in-process nodes are seen at once)."""


def run_session(
    config: LaunchConfig,
    packages: PackageIndex,
    args: argparse.Namespace,
    *,
    script: tuple[LaunchNode, Path, list[str]] | None = None,
    sim_time: bool = True,
    quiet_end: bool = False,
    join: bool = False,
    announce: bool = False,
) -> int:
    """Start everything ``config`` asks for on one graph (and ``script``: a user's script
    run as that node, with those arguments) and run until Ctrl-C, ``--duration``, or a
    required node exits. ``sim_time``: the graph's time is simulated (``/clock``,
    ``/use_sim_time``), else the wall clock's, as with a bare roscore. ``quiet_end``: a
    required node's exit ends the run without a word, and its exit status is the run's
    (rosrun's way). ``join``: the nodes join the graph that is running (its parameters, its
    clock) instead of making one, as ROS nodes join a running master. ``announce``: roslaunch's
    way: say each process started, and each node lives and dies as roslaunch's processes do
    (:mod:`belvedere.launch._lifecycle`)."""
    if join:
        graph = join_graph(args, alone=sim_time)
        transport = graph.transport
        join = not getattr(transport, "serve_params", False)
    else:
        transport = open_clock_transport(args, clock=sim_time)
        graph = Graph(sim_time=sim_time, seed=args.seed, transport=transport)
    _hold_time_base(config, graph)
    runtime = LaunchRuntime(
        config,
        graph,
        packages,
        headless=args.headless,
        announce=announce,
        lifecycle=announce,
        joined=join,
        screen_stdout=2 if getattr(args, "echo", None) else None,  # --echo's is stdout
        viewer_options={
            "host": args.host,
            "port": args.port,
            "allow_origins": args.allow_origins,
        },
    )
    status = 0
    bridge = None
    try:
        if join:
            _share_params(graph, config)
        bridge = start_foxglove(args, graph)
        runtime.start()
        if script is not None and not runtime.run_script(script[0], script[1], argv=script[2]):
            return 1
        suffix = f"_{os.getpid()}" if join else ""
        install_script(graph, ScriptOptions.from_args(args), name=f"belvedere_script{suffix}")
        ended = _run(graph, runtime, args, quiet_end=quiet_end)
        if ended is not None and quiet_end:
            status = runtime.exit_status(ended)
    except KeyboardInterrupt:
        pass
    finally:
        sys.stdout.flush()
        if bridge is not None:
            bridge.close()
        runtime.close()
        graph.shutdown()
    return status


def _hold_time_base(config: LaunchConfig, graph: Graph) -> None:
    """One time base for the whole graph, as ROS has one master clock: the process that
    made the graph decided it (a launch simulates time, so ``/use_sim_time`` is true and its
    ``/clock`` runs from 0; a script run alone is on the wall clock), and every process
    that joins follows it. A launch's own ``/use_sim_time`` saying otherwise is not set
    (nodes in other processes would read it and stamp in another time than this one's
    nodes): one warning says which time wins and why."""
    param = config.params.get(USE_SIM_TIME)
    if param is None or bool(param.value) == graph.sim_time:
        return
    del config.params[USE_SIM_TIME]
    where = f"{param.source}: " if param.source is not None else ""
    said = "true" if param.value else "false"
    if graph.executor.following:
        why = "the running graph simulates time (it publishes /clock)"
    elif graph.sim_time:
        why = "this launch simulates time (it publishes /clock, from 0)"
    else:
        why = "the running graph is on the wall clock (as its first process started it)"
    logger.warning(
        "warning: %s/use_sim_time %s is not used: %s, so /use_sim_time stays %s and every "
        "process on the graph (launches, scripts, tools) keeps that one time",
        where,
        said,
        why,
        "true" if graph.sim_time else "false",
    )


def _share_params(graph: Graph, config: LaunchConfig) -> None:
    """The run's own parameters (rosrun's ``_name:=value``) are set on the running graph's
    parameter server too, as rosrun sets them on the master."""
    transport = graph.transport
    request = getattr(transport, "param_request", None)
    if request is None:
        return
    for name, param in config.params.items():
        try:
            request({"op": "set", "name": name, "value": param.value})
        except GraphError as err:
            logger.warning("cannot set %s on the running graph: %s", name, err.message)


def _nothing() -> None:
    pass


def _run(
    graph: Graph,
    runtime: LaunchRuntime,
    args: argparse.Namespace,
    *,
    quiet_end: bool,
) -> LaunchNode | None:
    """Run the graph; the required node whose end ended the run, if one did."""
    started = time.monotonic()
    last_check = [0.0]
    ended: list[LaunchNode] = []

    def required_exited() -> bool:
        spec = runtime.ended_in_process()
        if spec is None:
            now = time.monotonic()
            if now - last_check[0] < PROCESS_POLL_S:
                return False
            last_check[0] = now
            spec = runtime.poll_processes()
        if spec is not None:
            ended.append(spec)
            if not quiet_end and runtime.monitor is None:  # the monitor said it its way
                sys.stderr.write(f"required node {spec.full_name} exited: shutting down\n")
            return True
        return False

    stop = threading.Event()
    if not graph.sim_time or graph.executor.following:
        # Time may stand still here (no timer due on the wall clock, a paused simulation's
        # clock): wake the executor now and then to look at the processes.
        def wake() -> None:
            while not stop.wait(PROCESS_POLL_S):
                graph.executor.post(_nothing)

        threading.Thread(target=wake, name="belvedere-run-waker", daemon=True).start()
    try:
        graph.run(duration=args.duration, rtf=args.rtf, until=required_exited)
    finally:
        stop.set()
    if args.duration is not None:
        wall = time.monotonic() - started
        sys.stderr.write(f"simulated {args.duration:g} s in {wall:.3f} s\n")
    return ended[0] if ended else None
