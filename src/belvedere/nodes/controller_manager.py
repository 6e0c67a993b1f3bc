"""controller_manager: the spawner (and the old ``controller_manager spawn|load``)."""

from __future__ import annotations

import shlex

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter, StartError

__all__ = ["EXECUTABLES", "PACKAGE"]

PACKAGE = "controller_manager"


def _spawner(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.sim.physics import spawner

    words = shlex.split(spec.args)
    if spec.type == "controller_manager":
        if not words or words[0] not in ("spawn", "load"):
            msg = "controller_manager: expected 'spawn NAME…' or 'load NAME…'"
            raise StartError(msg, spec.source)
        words = words[1:] + (["--stopped"] if words[0] == "load" else [])

    def spawn() -> None:
        spawner(node, words, namespace=spec.namespace)

    session.controllers.append(spawn)


EXECUTABLES: dict[str, Starter] = {"spawner": _spawner, "controller_manager": _spawner}
