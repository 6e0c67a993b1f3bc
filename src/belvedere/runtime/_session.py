"""A session: a launch configuration run on one graph until it ends (``launch`` and ``run``
share it): the graph made or joined, its time base held, parameters shared, the bridge
and the scripted run's node beside it."""

from __future__ import annotations

import logging
import os
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from belvedere.graph import Graph, GraphError, graph_running
from belvedere.runtime._bridge import BridgeOptions, start_bridge
from belvedere.runtime._clock import hold_time_base, open_clock_transport
from belvedere.runtime._join import GraphAddress, join_graph, join_ros_master
from belvedere.runtime._scripted import EchoWait, ScriptOptions, install_script

if TYPE_CHECKING:
    from belvedere.launch import LaunchConfig, LaunchNode
    from belvedere.launch._runtime import LaunchRuntime
    from belvedere.packages import PackageIndex

__all__ = [
    "SessionOptions",
    "ViewerOptions",
    "joins_running_graph",
    "run_launch",
    "run_session",
]

logger = logging.getLogger(__name__)

PROCESS_POLL_S = 0.2
"""How often subprocesses are looked at (in-process nodes are seen at once)."""


@dataclass(frozen=True)
class ViewerOptions:
    """Where the viewer (rviz, gzclient) is served, and who may use it."""

    host: str = "127.0.0.1"
    """The address it listens on (another than this machine's needs the URL's token)."""
    port: int = 8080
    allow_origins: tuple[str, ...] = ()
    """Web origins besides the viewer's own page that may open its websocket."""


@dataclass(frozen=True)
class SessionOptions:
    """How a session runs: what the command line's options say, as plain values."""

    address: GraphAddress = field(default_factory=GraphAddress)
    """The graph to make or join."""
    seed: int = 0
    """The simulation's randomness."""
    duration: float | None = None
    """Seconds of the graph's time to run; None: until Ctrl-C or a required node ends."""
    rtf: float | None = 1.0
    """Real-time factor; None: as fast as possible."""
    headless: bool = False
    """No viewer (rviz, gzclient)."""
    viewer: ViewerOptions = field(default_factory=ViewerOptions)
    bridge: BridgeOptions | None = None
    """The Foxglove bridge beside the graph, if one is wanted."""
    pubs: tuple[str, ...] = ()
    """``'TOPIC TYPE YAML'``: messages published once at start, latched
    (:meth:`ScriptOptions.parse`)."""
    echoes: tuple[str, ...] = ()
    """Topics printed to stdout as YAML documents; stdout is then theirs alone (scripts'
    screen output goes to stderr)."""


def run_launch(config: LaunchConfig, packages: PackageIndex, options: SessionOptions) -> int:
    """roslaunch's way: :func:`run_session` announcing each process, nodes living and dying
    as roslaunch's; a launch of clients only joins the graph that runs
    (:func:`joins_running_graph`)."""
    join = joins_running_graph(config, options.address)
    return run_session(config, packages, options, announce=True, join=join)


def joins_running_graph(config: LaunchConfig, address: GraphAddress) -> bool:
    """As roslaunch uses the master that runs: a launch of clients only (amcl, move_base,
    rviz, scripts …) beside a running simulation joins its graph, with its parameters and
    its clock. A launch that starts a simulator makes the graph and its clock, as before."""
    if not graph_running(address.endpoint, address.domain):
        return False
    from belvedere import nodes

    return all(
        nodes.find(n.pkg, n.type) is None or nodes.joins_running_graph(n.pkg, n.type)
        for n in config.nodes
    )


def run_session(
    config: LaunchConfig,
    packages: PackageIndex,
    options: SessionOptions,
    *,
    script: tuple[LaunchNode, Path, list[str]] | None = None,
    sim_time: bool = True,
    quiet_end: bool = False,
    join: bool = False,
    announce: bool = False,
) -> int:
    """Start everything ``config`` asks for on one graph (and ``script``: a user's script
    run as that node, with those arguments) and run until Ctrl-C, ``options.duration``, or
    a required node exits; the run's exit status. ``sim_time``: the graph's time is
    simulated (``/clock``, ``/use_sim_time``), else the wall clock's, as with a bare roscore.
    ``quiet_end``: a required node's exit ends the run without a word, and its exit status is
    the run's (rosrun's way). ``join``: the nodes join the graph that is running (its
    parameters, its clock) instead of making one, as ROS nodes join a running master.
    ``announce``: roslaunch's way: say each process started, and each node lives and dies
    as roslaunch's processes do (:mod:`belvedere.launch._lifecycle`)."""
    from belvedere.launch._runtime import LaunchRuntime
    from belvedere.msgs import types

    # the run's own packages' types (--echo, --pub, a bag), as its scripts find them
    types().add_package_path(packages.search_path)
    if join:
        graph = join_graph(options.address, seed=options.seed, alone=sim_time)
        transport = graph.transport
        join = not getattr(transport, "serve_params", False)
    else:
        transport = open_clock_transport(options.address, clock=sim_time)
        graph = Graph(sim_time=sim_time, seed=options.seed, transport=transport)
        join_ros_master(graph, options.address)
    hold_time_base(config, graph)
    runtime = LaunchRuntime(
        config,
        graph,
        packages,
        headless=options.headless,
        announce=announce,
        lifecycle=announce,
        joined=join,
        screen_stdout=2 if options.echoes else None,  # --echo's is stdout
        viewer_options={
            "host": options.viewer.host,
            "port": options.viewer.port,
            "allow_origins": options.viewer.allow_origins,
        },
    )
    status = 0
    bridge = None
    echo_wait: EchoWait | None = None
    try:
        if join:
            _share_params(graph, config)
        bridge = start_bridge(graph, options.bridge)
        runtime.start()
        if script is not None and not runtime.run_script(script[0], script[1], argv=script[2]):
            return 1
        suffix = f"_{os.getpid()}" if join else ""
        scripted = ScriptOptions.parse(options.pubs, options.echoes, duration=options.duration)
        # a script's topics are known once its process advertises them; the built-in
        # nodes' are known now, so a misspelt --echo is refused before the run
        learns = join or script is not None or _has_scripts(config)
        echo_wait = install_script(
            graph, scripted, name=f"belvedere_script{suffix}", learns_topics=learns
        )
        ended = _run(graph, runtime, options, quiet_end=quiet_end)
        if ended is not None and quiet_end:
            status = runtime.exit_status(ended)
    except KeyboardInterrupt:
        pass
    finally:
        sys.stdout.flush()
        for topic in echo_wait.close() if echo_wait is not None else ():
            sys.stderr.write(f"--echo {topic}: no node of this run published it\n")
        if bridge is not None:
            bridge.close()
        runtime.close()
        graph.shutdown()
    return status


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


def _has_scripts(config: LaunchConfig) -> bool:
    """Whether a launch runs a script (a node belvedere does not have: its own process)."""
    from belvedere import nodes

    return any(nodes.find(n.pkg, n.type) is None for n in config.nodes)


def _nothing() -> None:
    pass


def _run(
    graph: Graph,
    runtime: LaunchRuntime,
    options: SessionOptions,
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
        graph.run(duration=options.duration, rtf=options.rtf, until=required_exited)
    finally:
        stop.set()
    if options.duration is not None:
        wall = time.monotonic() - started
        sys.stderr.write(f"simulated {options.duration:g} s in {wall:.3f} s\n")
    return ended[0] if ended else None
