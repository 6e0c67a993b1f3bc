"""rviz: the browser viewer, with the displays of an ``.rviz`` file (``-d FILE``)."""

from __future__ import annotations

import shlex

from belvedere.graph import Node
from belvedere.nodes._registry import FileClaim, NodeSpec, Session, Starter

__all__ = ["ANONYMOUS", "EXECUTABLES", "FILES", "JOINING", "PACKAGE"]

PACKAGE = "rviz"


def _config(spec: NodeSpec) -> str | None:
    """The ``-d FILE`` (``--display-config FILE``) of rviz's arguments, if any."""
    words = shlex.split(spec.args)
    config = None
    for flag in ("-d", "--display-config"):
        if flag in words and words.index(flag) + 1 < len(words):
            config = words[words.index(flag) + 1]
    return config


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    config = _config(spec)
    if config is not None:
        session.rviz_config = config
    session.want_viewer = True


def _files(spec: NodeSpec) -> list[tuple[str, str]]:
    config = _config(spec)
    return [] if config is None else [("rviz", config)]


EXECUTABLES: dict[str, Starter] = {"rviz": _start}
FILES: dict[str, FileClaim] = {"rviz": _files}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset({"rviz"})
"""Named as roscpp's ``AnonymousName`` names it when run without ``__name:=``."""
