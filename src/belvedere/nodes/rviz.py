"""rviz: the browser viewer, with the displays of an ``.rviz`` file (``-d FILE``)."""

from __future__ import annotations

import shlex

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter

__all__ = ["ANONYMOUS", "EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "rviz"


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    words = shlex.split(spec.args)
    for flag in ("-d", "--display-config"):
        if flag in words and words.index(flag) + 1 < len(words):
            session.rviz_config = words[words.index(flag) + 1]
    session.want_viewer = True


EXECUTABLES: dict[str, Starter] = {"rviz": _start}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset({"rviz"})
"""Named as roscpp's ``AnonymousName`` names it when run without ``__name:=``."""
