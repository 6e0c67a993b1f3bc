"""rqt_tf_tree: the TF tree heard on /tf and /tf_static as a live picture on a page of its own
(its URL printed), each edge with its broadcaster, rate, latest transform and buffer length."""

from __future__ import annotations

from belvedere.graph import Node
from belvedere.nodes._pictures import serve_page, watch_frames
from belvedere.nodes._registry import NodeSpec, Session, Starter

__all__ = ["ANONYMOUS", "EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "rqt_tf_tree"


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    watch = watch_frames(session, spec, node)
    serve_page(session, node, "rqt_tf_tree", lambda _query: watch.dot())


EXECUTABLES: dict[str, Starter] = {"rqt_tf_tree": _start}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset(EXECUTABLES)
"""rqt names its node anonymously, so two can run."""
