"""The running graph as rqt_graph draws it: nodes as ellipses, topics as boxes, each name
inside the cluster of its namespace, in rqt_graph's three modes and with its filters."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final, Literal

from belvedere.graph import GraphInfo

__all__ = ["MODES", "GraphView", "graph_dot", "quote"]

Mode = Literal["nodes", "active", "all"]
MODES: Final[dict[str, Mode]] = {
    "Nodes only": "nodes",
    "Nodes/Topics (active)": "active",
    "Nodes/Topics (all)": "all",
}
"""rqt_graph's mode menu: its label → the mode's key here."""

DEBUG_NAMES: Final = ("/rosout", "/rosout_agg", "/clock", "/statistics", "/rqt", "/rostopic")
"""Names rqt_graph's "Debug" filter hides (with what starts with them)."""
OWN_HELPERS: Final = "/belvedere_"
"""belvedere's own helper nodes (the clock, the viewer, a tool's node) start so."""


@dataclass(frozen=True)
class GraphView:
    """What the picture shows, as rqt_graph's controls choose it."""

    mode: Mode = "active"
    hide_debug: bool = True
    """/rosout, /clock, rqt's and belvedere's helper nodes."""
    hide_dead_sinks: bool = True
    """Topics that are published and read by nobody."""
    hide_leaf_topics: bool = False
    """Topics with publishers only or subscribers only."""
    group_namespaces: bool = True

    @classmethod
    def from_query(cls, query: dict[str, list[str]]) -> GraphView:
        """The view a page's query asks for (``mode=all&debug=0…``); unknown values keep the
        default, as a page control can only send known ones."""

        def flag(name: str, default: bool) -> bool:
            value = query.get(name, [""])[-1]
            return default if value not in ("0", "1") else value == "1"

        mode = query.get("mode", [""])[-1]
        return cls(
            mode=mode if mode in ("nodes", "active", "all") else "active",  # type: ignore[arg-type]
            hide_debug=flag("debug", True),
            hide_dead_sinks=flag("dead", True),
            hide_leaf_topics=flag("leaf", False),
            group_namespaces=flag("groups", True),
        )


def quote(text: str) -> str:
    """``text`` as a Graphviz string (names come from peers: nothing in them is syntax)."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _debug(name: str) -> bool:
    return name.startswith(OWN_HELPERS) or any(
        name == d or name.startswith((d + "/", d + "_")) for d in DEBUG_NAMES
    )


def _namespace(name: str) -> str:
    return name.rsplit("/", 1)[0] or "/"


def graph_dot(info: GraphInfo, view: GraphView, *, hidden: frozenset[str] = frozenset()) -> str:
    """The picture of ``info`` in Graphviz's language. ``hidden``: nodes never drawn (the
    picture's own node)."""
    nodes = {n for n in info.nodes if n not in hidden and not (view.hide_debug and _debug(n))}
    pubs = {t: {n for _, n in s if n in nodes} for t, s in info.publishers.items()}
    subs = {t: {n for _, n in s if n in nodes} for t, s in info.subscribers.items()}
    topics = set()
    for topic in set(pubs) | set(subs):
        out, into = pubs.get(topic, set()), subs.get(topic, set())
        if (view.hide_debug and _debug(topic)) or not (out or into):
            continue
        if view.mode != "all" and not (out and into):
            continue  # active: a topic that connects a publisher to a subscriber
        if view.hide_dead_sinks and not into:
            continue
        if view.hide_leaf_topics and not (out and into):
            continue
        topics.add(topic)
    if view.mode != "nodes":
        nodes = {n for n in nodes if view.mode == "all" or _connected(n, topics, pubs, subs)}
    lines = ["digraph rqt_graph {", "  graph [rankdir=LR];", '  node [fontname="sans"];']
    shapes = [(n, f"n_{n}", "ellipse") for n in sorted(nodes)]
    if view.mode != "nodes":
        shapes += [(t, f"t_{t}", "box") for t in sorted(topics)]
    clusters: dict[str, list[str]] = {}
    for name, ident, shape in shapes:
        where = _namespace(name) if view.group_namespaces else "/"
        line = f"{quote(ident)} [label={quote(name)}, shape={shape}];"
        clusters.setdefault(where, []).append(line)
    for where, members in sorted(clusters.items()):
        if where == "/":
            lines += ["  " + m for m in members]
            continue
        lines.append(f"  subgraph {quote('cluster_' + where)} {{")
        lines.append(f"    label={quote(where)}; style=rounded; color=gray40;")
        lines += ["    " + m for m in members]
        lines.append("  }")
    lines += _edges(view, nodes, topics, pubs, subs)
    lines.append("}")
    return "\n".join(lines) + "\n"


def _connected(
    node: str, topics: set[str], pubs: dict[str, set[str]], subs: dict[str, set[str]]
) -> bool:
    return any(node in pubs.get(t, ()) or node in subs.get(t, ()) for t in topics)


def _edges(
    view: GraphView,
    nodes: set[str],
    topics: set[str],
    pubs: dict[str, set[str]],
    subs: dict[str, set[str]],
) -> list[str]:
    if view.mode == "nodes":
        # node → node, one edge per topic that joins them, labelled with it
        return [
            f"  {quote('n_' + a)} -> {quote('n_' + b)} [label={quote(topic)}];"
            for topic in sorted(set(pubs) & set(subs))
            if not (view.hide_debug and _debug(topic))
            for a in sorted(pubs[topic] & nodes)
            for b in sorted(subs[topic] & nodes)
            if a != b
        ]
    lines = []
    for topic in sorted(topics):
        into = quote("t_" + topic)
        lines += [f"  {quote('n_' + n)} -> {into};" for n in sorted(pubs.get(topic, ()))]
        lines += [f"  {into} -> {quote('n_' + n)};" for n in sorted(subs.get(topic, ()))]
    return lines
