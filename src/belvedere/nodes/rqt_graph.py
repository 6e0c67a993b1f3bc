"""rqt_graph: the running graph's nodes and topics as a live picture, on a page of its own
(its URL printed), with rqt_graph's modes and filters."""

from __future__ import annotations

from belvedere.graph import Node
from belvedere.nodes._pictures import needs_dot, serve_page
from belvedere.nodes._registry import NodeSpec, Session, Starter
from belvedere.pictures import MODES, GraphView, graph_dot, graph_info

__all__ = ["ANONYMOUS", "CONTROLS", "EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "rqt_graph"

_OPTIONS = "".join(
    f'<option value="{key}"{" selected" if key == "active" else ""}>{label}</option>'
    for label, key in MODES.items()
)
CONTROLS = (
    f'<select name="mode">{_OPTIONS}</select> Hide: '
    '<label><input type="checkbox" name="debug" checked> Debug</label>'
    '<label><input type="checkbox" name="dead" checked> Dead sinks</label>'
    '<label><input type="checkbox" name="leaf"> Leaf topics</label> '
    '<label><input type="checkbox" name="groups" checked> Group namespaces</label>'
)
"""The page's controls, as rqt_graph's toolbar has them."""


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    needs_dot(spec)
    own = frozenset({node.full_name})

    def draw(query: dict[str, list[str]]) -> str:
        return graph_dot(graph_info(session.graph), GraphView.from_query(query), hidden=own)

    serve_page(session, node, "rqt_graph", draw, controls=CONTROLS)


EXECUTABLES: dict[str, Starter] = {"rqt_graph": _start}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset(EXECUTABLES)
"""rqt names its node anonymously, so two can run."""
