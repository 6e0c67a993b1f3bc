"""teleop_twist_keyboard: drive /cmd_vel from the terminal's keys."""

from __future__ import annotations

import logging
import sys

from belvedere.graph import Node
from belvedere.msgs import types
from belvedere.nodes._keyboard import drive_from_terminal
from belvedere.nodes._registry import NodeSpec, Session, Starter

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "teleop_twist_keyboard"
logger = logging.getLogger("belvedere.launch")


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    if not sys.stdin.isatty():
        logger.warning(
            "%s: teleop_twist_keyboard needs a terminal; run 'belvedere teleop' in one",
            spec.source,
        )
        return
    from belvedere.teleop import TwistKeyboard

    pub = node.publisher("cmd_vel", "geometry_msgs/Twist", queue_size=1)
    twist, vector = types().cls("geometry_msgs/Twist"), types().cls("geometry_msgs/Vector3")
    speed = float(node.get_param("~speed", 0.5))
    turn = float(node.get_param("~turn", 1.0))

    def publish(t: tuple[float, float, float, float]) -> None:
        pub.publish(twist(vector(t[0], t[1], t[2]), vector(0.0, 0.0, t[3])))

    # q or Ctrl-C ends the key loop, and the node with it, as teleop_twist_keyboard.py exits
    drive_from_terminal(session, node, TwistKeyboard(speed, turn), publish)


EXECUTABLES: dict[str, Starter] = {"teleop_twist_keyboard.py": _start}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
