"""roswtf's online checks that a learner needs, on a running graph: subscriptions nothing
publishes, publications nothing subscribes to, ``/use_sim_time`` without a ``/clock``, and
a TF tree that is broken (a frame with two parents, a loop, frames in more than one tree).

The first and third say what roswtf says (its words); the others are belvedere's own checks
(roswtf's TF checks need transforms' authorities and a running tf2 graph)."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any, Final

from belvedere.graph import GraphInfo
from belvedere.runtime._join import Tool, running_params

__all__ = ["WtfReport", "check_graph"]

_QUIET_SUBSCRIPTIONS: Final = frozenset({"/time", "/clock"})
"""Subscribed with nothing publishing, and fine: the clock a node follows when there is one
(roswtf's own exception outside simulated time)."""
_QUIET_PUBLICATIONS: Final = frozenset(
    {"/rosout", "/rosout_agg", "/clock", "/tf", "/tf_static", "/joint_states"}
)
"""Published whether or not anything listens, as ROS's nodes do: no warning for these."""


@dataclass
class WtfReport:
    """What roswtf would print: its warnings and errors, each a message (several lines)."""

    warnings: list[str] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)

    def text(self) -> str:
        """roswtf's summary of its online checks."""
        if not self.warnings and not self.errors:
            return "No errors or warnings\n"
        out: list[str] = []
        if self.warnings:
            out.append(
                f"Found {len(self.warnings)} warning(s).\n"
                "Warnings are things that may be just fine, but are sometimes at fault\n"
            )
            out += [f"WARNING {w}" for w in self.warnings]
            out.append("")
        if self.errors:
            out.append(f"Found {len(self.errors)} error(s).\n")
            out += [f"ERROR {e}" for e in self.errors]
        return "\n".join(out) + "\n"


def _by_node(rows: Iterable[tuple[str, str]]) -> str:
    """`` * node:`` then ``   * topic`` under it, as roswtf lists them."""
    nodes: dict[str, list[str]] = {}
    for node, topic in sorted(rows):
        nodes.setdefault(node, []).append(topic)
    return "".join(
        f" * {node}:\n" + "".join(f"   * {topic}\n" for topic in topics)
        for node, topics in nodes.items()
    )


def _unconnected(info: GraphInfo, own: str, sim_time: bool) -> tuple[str, str]:
    quiet = {"/reset_time"} if sim_time else _QUIET_SUBSCRIPTIONS
    lonely_subs = [
        (node, topic)
        for topic, entries in info.subscribers.items()
        for _, node in entries
        if node != own and topic not in quiet and not info.publishers.get(topic)
    ]
    lonely_pubs = [
        (node, topic)
        for topic, entries in info.publishers.items()
        for _, node in entries
        if node != own and topic not in _QUIET_PUBLICATIONS and not info.subscribers.get(topic)
    ]
    return _by_node(lonely_subs), _by_node(lonely_pubs)


def _frame(name: str) -> str:
    return name.lstrip("/")  # tf2 drops a leading slash


def _tf_problems(parents: dict[str, set[str]]) -> list[str]:
    """A frame with two parents; loops; frames in more than one tree."""
    problems: list[str] = []
    several = {child: ps for child, ps in parents.items() if len(ps) > 1}
    if several:
        problems.append(
            "The following TF frames have more than one parent (a frame has one):\n"
            + "".join(f" * {c}: {', '.join(sorted(ps))}\n" for c, ps in sorted(several.items()))
        )
    edges = {child: sorted(ps) for child, ps in parents.items()}
    loops: set[tuple[str, ...]] = set()
    roots: dict[str, set[str]] = {}
    for start in sorted({*edges, *(p for ps in edges.values() for p in ps)}):
        path = [start]
        while path[-1] in edges:
            up = edges[path[-1]][0]
            if up in path:
                loop = path[path.index(up) :]
                turn = loop.index(min(loop))
                loops.add(tuple(loop[turn:] + loop[:turn]))
                break
            path.append(up)
        else:
            roots.setdefault(path[-1], set()).add(start)
    if loops:
        problems.append(
            "The TF frames form a loop (each frame's parents lead back to it):\n"
            + "".join(f" * {' -> '.join([*loop, loop[0]])}\n" for loop in sorted(loops))
        )
    if len(roots) > 1:
        problems.append(
            "The TF frames form more than one tree (no transform between the trees):\n"
            + "".join(
                f" * {root}: {', '.join(sorted(frames))}\n"
                for root, frames in sorted(roots.items())
            )
        )
    return problems


def _listen_tf(tool: Tool, seconds: float) -> dict[str, set[str]]:
    """child → its parents, as heard on /tf and /tf_static (latched: all of it) within
    ``seconds`` of wall time."""
    parents: dict[str, set[str]] = {}
    lock = threading.Lock()

    def heard(msg: Any) -> None:
        with lock:
            for t in msg.transforms:
                child, parent = _frame(t.child_frame_id), _frame(t.header.frame_id)
                parents.setdefault(child, set()).add(parent)

    for topic in ("/tf", "/tf_static"):
        tool.node.subscribe(topic, "tf2_msgs/TFMessage", heard, queue_size=100)
    tool.graph.start(rtf=None)
    time.sleep(seconds)  # transforms come at their publishers' rates: listen a while
    with lock:
        return {child: set(ps) for child, ps in parents.items()}


def check_graph(tool: Tool, *, listen: float = 1.0) -> WtfReport:
    """roswtf's online checks on the graph the tool is on (``listen``: seconds to hear
    transforms)."""
    sim_time = bool((running_params(tool.transport) or {}).get("use_sim_time", False))
    parents = _listen_tf(tool, listen)
    info = tool.info()
    report = WtfReport()
    subs, pubs = _unconnected(info, tool.node.full_name, sim_time)
    if subs:
        report.warnings.append("The following node subscriptions are unconnected:\n" + subs)
    if pubs:
        report.warnings.append("The following node publications have no subscribers:\n" + pubs)
    if sim_time and not (info.publishers.get("/clock") or info.publishers.get("/time")):
        report.errors.append("/use_sim_time is set but no publisher of /clock is present")
    report.errors += _tf_problems(parents)
    return report
