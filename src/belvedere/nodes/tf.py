"""tf: static_transform_publisher."""

from __future__ import annotations

import shlex

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter
from belvedere.tf import static_transform_publisher

__all__ = ["EXECUTABLES", "PACKAGE", "static_publisher"]

PACKAGE = "tf"


def static_publisher(session: Session, spec: NodeSpec, node: Node) -> None:
    static_transform_publisher(node, shlex.split(spec.args))


EXECUTABLES: dict[str, Starter] = {"static_transform_publisher": static_publisher}
