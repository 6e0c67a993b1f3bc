"""What rosnode, rostopic find and rosservice info ask of a running graph, below the command
line: known names (or an error with the closest), a node's process pinged or asked to end,
the machines nodes run on, the services of a type.

belvedere's graph has no master and no XML-RPC: a node is known from its process's
liveliness tokens, and its process answers for it (``ping``, ``kill``) on the graph's Zenoh
network (:meth:`~belvedere.graph.ZenohTransport.node_request`).
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from dataclasses import dataclass

from belvedere.errors import BelvedereError
from belvedere.graph import GraphInfo, did_you_mean, resolve_name
from belvedere.runtime._join import Tool, wait_for

__all__ = [
    "Pong",
    "kill_nodes",
    "known_node",
    "machines",
    "offered_service",
    "ping_node",
    "unreachable_nodes",
]


def known_node(info: GraphInfo, name: str, *, besides: Iterable[str] = ()) -> str:
    """The resolved name of a node on the graph, or an error naming the closest ones
    (``besides``: nodes not to suggest, a tool's own)."""
    full = resolve_name(name)
    if full not in info.nodes:
        others = info.nodes - set(besides)
        hint = did_you_mean(full, others) or "see 'belvedere node list'"
        msg = f"unknown node {full}"
        raise BelvedereError(msg, hint=hint)
    return full


def offered_service(info: GraphInfo, name: str) -> tuple[str, str, set[tuple[str, str]]]:
    """(resolved name, type, {(type, node)}) of an offered service, or an error naming the
    closest offered ones."""
    full = resolve_name(name)
    offered = info.services.get(full, set())
    if not offered:
        msg = f"service {full} is not offered by any node"
        hint = did_you_mean(full, info.services) or "see 'belvedere service list'"
        raise BelvedereError(msg, hint=hint)
    return full, sorted(offered)[0][0], offered


@dataclass(frozen=True)
class Pong:
    """A node's process answered: where it runs, and the round trip."""

    node: str
    process: str
    """``pid 1234 on host``"""
    ms: float


def ping_node(tool: Tool, node: str, timeout: float = 3.0) -> Pong | None:
    """One round trip to the process holding ``node`` (None: no answer within ``timeout``)."""
    start = time.perf_counter()
    answer = tool.transport.node_request(node, "ping", caller=tool.node.full_name, timeout=timeout)
    ms = (time.perf_counter() - start) * 1000.0
    if answer is None:
        return None
    return Pong(node, f"pid {answer['pid']} on {answer['host']}", ms)


def kill_nodes(tool: Tool, nodes: Iterable[str], timeout: float = 5.0) -> list[str]:
    """Ask each node's process to shut it down (rosnode kill), then wait for them to leave
    the graph; the nodes still on it after ``timeout`` (their process did not answer)."""
    asked = list(nodes)
    for node in asked:
        tool.transport.node_request(node, "kill", caller=tool.node.full_name, timeout=timeout)

    def left() -> bool:
        return not set(asked) & tool.info().nodes

    wait_for(left, timeout)
    return sorted(set(asked) & tool.info().nodes)


def machines(info: GraphInfo) -> dict[str, set[str]]:
    """host → the nodes whose processes run there."""
    hosts: dict[str, set[str]] = {}
    for node, processes in info.processes.items():
        for process in processes:
            hosts.setdefault(process.rpartition(" on ")[2], set()).add(node)
    return hosts


def unreachable_nodes(tool: Tool, info: GraphInfo, timeout: float = 1.0) -> list[str]:
    """The nodes whose process does not answer (stopped, or hung): what rosnode cleanup
    would purge. A process that ended is no longer on the graph at all."""
    own = tool.node.full_name
    return sorted(
        node for node in info.nodes - {own} if ping_node(tool, node, timeout=timeout) is None
    )
