"""joint_state_publisher_gui: joint_state_publisher with sliders (the viewer's)."""

from __future__ import annotations

from belvedere.nodes._registry import Starter
from belvedere.nodes.joint_state_publisher import start

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "joint_state_publisher_gui"
EXECUTABLES: dict[str, Starter] = {"joint_state_publisher_gui": start}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
