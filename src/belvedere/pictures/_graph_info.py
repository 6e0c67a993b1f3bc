"""Who is on the graph, for a picture of it: the graph's Zenoh peers when it has them, else
this process's own graph."""

from __future__ import annotations

from belvedere.graph import Graph, GraphInfo

__all__ = ["graph_info", "publishers_of"]

ASK_S = 0.5
"""How long the peers are given to answer (rosnode waits as long)."""


def graph_info(graph: Graph) -> GraphInfo:
    """The nodes, topics and services on ``graph``, across processes."""
    transport = graph.transport
    info_of = getattr(transport, "info", None)
    if info_of is not None:
        found: GraphInfo = info_of(timeout=ASK_S)
        return found
    info = GraphInfo()
    info.nodes.update(graph.nodes)
    for topic in list(graph.topics.values()):
        for pub in list(topic.publishers):
            info.publishers.setdefault(topic.name, set()).add((topic.type, pub.node.full_name))
        for sub in list(topic.subscriptions):
            info.subscribers.setdefault(topic.name, set()).add((topic.type, sub.node.full_name))
    return info


def publishers_of(graph: Graph, topic: str) -> set[str]:
    return {node for _, node in graph_info(graph).publishers.get(topic, ())}
