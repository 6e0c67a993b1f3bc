"""rqt_console: the graph's ``/rosout`` messages as a table in a browser page, with
rqt_console's filters. The page's port is the ``~port`` parameter (8091)."""

from __future__ import annotations

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter, stopping_on_bad_values
from belvedere.nodes._rqt import open_page

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "rqt_console"
PORT = 8091


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.viewer import ConsolePage

    console = ConsolePage(node, open_page(spec, node, PORT))
    session.closers.append(console.close)


EXECUTABLES: dict[str, Starter] = {"rqt_console": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
