"""tf: static_transform_publisher, and view_frames (the TF tree heard for five seconds,
written to ``frames.gv`` and ``frames.pdf`` in the working directory)."""

from __future__ import annotations

import shlex
import sys

from belvedere.graph import Node
from belvedere.nodes._pictures import watch_frames
from belvedere.nodes._registry import (
    NodeSpec,
    ParamLookup,
    Session,
    Starter,
    TransformClaim,
    end_node,
)
from belvedere.pictures import write_pictures
from belvedere.tf import parse_static_transform_args, static_transform_publisher

__all__ = [
    "ANONYMOUS",
    "EXECUTABLES",
    "JOINING",
    "PACKAGE",
    "TRANSFORMS",
    "static_claim",
    "static_publisher",
]

PACKAGE = "tf"


def static_publisher(session: Session, spec: NodeSpec, node: Node) -> None:
    static_transform_publisher(node, shlex.split(spec.args))


LISTEN_S = 5.0
"""How long view_frames listens, as tf's does."""


def view_frames(session: Session, spec: NodeSpec, node: Node) -> None:
    watch = watch_frames(session, spec, node)
    sys.stdout.write(f"Listening to /tf for {LISTEN_S:.1f} seconds\n")
    sys.stdout.flush()

    def done() -> None:
        sys.stdout.write("Done Listening\n")
        write_pictures(watch.dot(), "frames")
        sys.stdout.write("frames.pdf generated\n")
        sys.stdout.flush()
        end_node(session, node)

    node.timer(LISTEN_S, done, oneshot=True)


EXECUTABLES: dict[str, Starter] = {
    "static_transform_publisher": static_publisher,
    "view_frames": view_frames,
}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset({"static_transform_publisher", "view_frames"})
"""Named as roscpp's ``AnonymousName`` names it when run without ``__name:=``."""


def static_claim(spec: NodeSpec, param: ParamLookup) -> list[tuple[str, str]]:
    del param
    parent, child, _ = parse_static_transform_args(shlex.split(spec.args))
    return [(parent, child)]


TRANSFORMS: dict[str, TransformClaim] = {"static_transform_publisher": static_claim}
