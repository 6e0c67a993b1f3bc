"""arbotix_python: the ArbotiX driver, simulated (the kinematic engine)."""

from __future__ import annotations

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter

__all__ = ["EXECUTABLES", "PACKAGE"]

PACKAGE = "arbotix_python"


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.sim.kinematic import ArbotixDriver, DriverControls

    driver = ArbotixDriver(node)
    # the viewer's Reset, Pause and Step, as `belvedere sim` has them
    if session.sim_controls is None:
        session.sim_controls = DriverControls(session.graph)
    session.sim_controls.drivers.append(driver)


EXECUTABLES: dict[str, Starter] = {"arbotix_driver": _start}
