"""joint_state_publisher: every movable joint's state (sliders in the viewer with its GUI)."""

from __future__ import annotations

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter
from belvedere.tf import JointStatePublisher

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE", "start"]

PACKAGE = "joint_state_publisher"


def start(session: Session, spec: NodeSpec, node: Node) -> None:
    session.joint_publisher = JointStatePublisher(node)
    use_gui = node.get_param("use_gui", False) or node.get_param("~use_gui", False)
    if spec.pkg == "joint_state_publisher_gui" or use_gui is True or str(use_gui).lower() == "true":
        session.gui_joints = True
        session.want_viewer = True


EXECUTABLES: dict[str, Starter] = {"joint_state_publisher": start}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
