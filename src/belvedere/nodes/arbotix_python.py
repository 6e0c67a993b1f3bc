"""arbotix_python: the ArbotiX driver, simulated (the kinematic engine)."""

from __future__ import annotations

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter

__all__ = ["EXECUTABLES", "PACKAGE"]

PACKAGE = "arbotix_python"


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.sim.kinematic import ArbotixDriver

    ArbotixDriver(node)


EXECUTABLES: dict[str, Starter] = {"arbotix_driver": _start}
