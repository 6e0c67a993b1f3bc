"""The keyboard teleops' shared loop: keys read on a thread of their own, the node ended when
the loop ends (q or Ctrl-C), as turtle_teleop_key and teleop_twist_keyboard exit then."""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

from belvedere.graph import Node
from belvedere.nodes._registry import Session, end_when

if TYPE_CHECKING:
    from belvedere.teleop import Layout

__all__ = ["drive_from_terminal"]


def drive_from_terminal(
    session: Session,
    node: Node,
    layout: Layout,
    publish: Callable[[tuple[float, float, float, float]], None],
) -> None:
    """Read this process's terminal with ``layout`` on a thread, publishing what it says;
    ``node`` ends once the loop quits, so a ``run`` of it exits as the ROS executable does."""
    from belvedere.teleop import run_teleop  # termios and the layouts, only when a teleop runs

    thread = threading.Thread(
        target=run_teleop, args=(layout, publish, sys.stdin.fileno(), sys.stdout), daemon=True
    )
    thread.start()
    end_when(session, node, lambda: not thread.is_alive())
