"""rqt_image_view: an image topic in a browser page (``rqt_image_view [TOPIC]``; the
``image`` remapping names it too, as image_view's does), picked among the graph's image
topics. The page's port is the ``~port`` parameter (8092)."""

from __future__ import annotations

import shlex

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter, StartError, stopping_on_bad_values
from belvedere.nodes._rqt import open_page, words

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "rqt_image_view"
PORT = 8092


def _topic(spec: NodeSpec, node: Node) -> str | None:
    args = words(spec)
    if len(args) > 1 or any(a.startswith("-") for a in args):
        msg = f"{spec.full_name}: rqt_image_view takes one image topic, got {shlex.join(args)}"
        raise StartError(msg, spec.source)
    if args:
        return node.resolve(args[0])
    for word in shlex.split(spec.args):
        if word.startswith("image:="):
            return node.resolve(word.removeprefix("image:="))
    return None


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.viewer import ImagePage

    topic = _topic(spec, node)
    view = ImagePage(node, open_page(spec, node, PORT), topic)
    session.closers.append(view.close)


EXECUTABLES: dict[str, Starter] = {"rqt_image_view": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
