"""The clock policy: a graph has one clock, and the process that makes the graph keeps its
time.

As ROS 1 has one master and Gazebo refuses a second server on it: a simulation starting
where another process already publishes ``/clock`` is refused
(:func:`refuse_second_clock`), and a launch's own ``/use_sim_time`` never contradicts the
time the graph's first process chose (:func:`hold_time_base`).
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Any

from belvedere.errors import BelvedereError
from belvedere.runtime._join import GraphAddress, open_transport, running_params

if TYPE_CHECKING:
    from belvedere.graph import Graph, ZenohTransport
    from belvedere.launch import LaunchConfig

__all__ = [
    "CLOCK",
    "USE_SIM_TIME",
    "hold_time_base",
    "open_clock_transport",
    "refuse_second_clock",
]

logger = logging.getLogger(__name__)

USE_SIM_TIME = "/use_sim_time"
CLOCK = "/clock"


def open_clock_transport(
    address: GraphAddress, *, clock: bool = True, **options: Any
) -> ZenohTransport:
    """:func:`~belvedere.runtime.open_transport` for a process that will publish ``/clock``
    (when ``clock``): refused, and closed, where another process already does
    (:func:`refuse_second_clock`)."""
    transport = open_transport(address, **options)
    if clock:
        try:
            refuse_second_clock(transport)
        except BelvedereError:
            transport.close()
            raise
    return transport


def refuse_second_clock(transport: ZenohTransport) -> None:
    """A simulation starting where another process already publishes ``/clock`` is an
    error naming that process: a graph has one clock (ROS 1 one master, and Gazebo refuses
    a second server on it); two would make ``/clock`` jump between their times."""
    if transport.role == "listen":
        return  # nothing else runs here
    info = transport.info(timeout=1.0)
    owners = sorted(
        {
            process
            for _, node in info.publishers.get(CLOCK, set())
            for process in info.processes.get(node, {node})
        }
    )
    if owners:
        msg = (
            f"a simulation already runs on this graph: {', '.join(owners)} publishes {CLOCK}, "
            "and a graph has one clock"
        )
        raise BelvedereError(
            msg,
            hint="stop it first (Ctrl-C in its terminal), or run this one on a graph of its "
            "own (--domain N)",
        )
    remote = running_params(transport)
    if remote is not None and not remote.get("use_sim_time", False):
        logger.warning(
            "warning: this graph already runs on the wall clock (the process that started it "
            "holds its parameters, /use_sim_time false): the processes that joined it keep "
            "the wall clock, not this simulated time; start the simulation first, or on a "
            "graph of its own (--domain N)"
        )


def hold_time_base(config: LaunchConfig, graph: Graph) -> None:
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
