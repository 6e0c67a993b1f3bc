"""robot_state_publisher: the robot's link transforms from its joint states."""

from __future__ import annotations

import logging

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter
from belvedere.tf import RobotStatePublisher

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "robot_state_publisher"
logger = logging.getLogger("belvedere.launch")


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    if spec.type == "state_publisher":
        logger.warning(
            "%s: robot_state_publisher's 'state_publisher' is deprecated; use "
            'type="robot_state_publisher"',
            spec.source,
        )
    RobotStatePublisher(node)


EXECUTABLES: dict[str, Starter] = {"robot_state_publisher": _start, "state_publisher": _start}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
