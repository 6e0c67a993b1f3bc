"""tf: static_transform_publisher."""

from __future__ import annotations

import shlex

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, ParamLookup, Session, Starter, TransformClaim
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


EXECUTABLES: dict[str, Starter] = {"static_transform_publisher": static_publisher}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset({"static_transform_publisher"})
"""Named as roscpp's ``AnonymousName`` names it when run without ``__name:=``."""


def static_claim(spec: NodeSpec, param: ParamLookup) -> list[tuple[str, str]]:
    del param
    parent, child, _ = parse_static_transform_args(shlex.split(spec.args))
    return [(parent, child)]


TRANSFORMS: dict[str, TransformClaim] = {"static_transform_publisher": static_claim}
