"""teleop_twist_keyboard from a real terminal: its keys drive /cmd_vel, and Ctrl-C ends the
run, as teleop_twist_keyboard.py exits when its key loop ends."""

from __future__ import annotations

import subprocess
import sys
from typing import Any

from belvedere.graph import Graph, ZenohTransport
from tests.terminal import Terminal
from tests.waiting import DEADLINE


def test_ctrl_c_ends_teleop_twist_keyboards_run(endpoint: str) -> None:
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    seen: list[Any] = []
    graph.create_node("watcher").subscribe("/cmd_vel", "geometry_msgs/Twist", seen.append)
    graph.start(rtf=None)
    terminal = Terminal()
    teleop = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "belvedere",
            "run",
            "teleop_twist_keyboard",
            "teleop_twist_keyboard.py",
        ],
        stdin=terminal.slave,
        stdout=terminal.slave,
        stderr=subprocess.DEVNULL,
    )
    try:
        terminal.wait_for("CTRL-C to quit")
        terminal.press_until("i", lambda: any(m.linear.x == 0.5 for m in seen), "/cmd_vel forward")
        terminal.type("\x03")  # Ctrl-C, read as a key in raw mode
        assert teleop.wait(timeout=DEADLINE) == 0
        assert seen[-1].linear.x == 0.0  # the loop's last word: stop
    finally:
        if teleop.poll() is None:
            teleop.kill()
            teleop.wait(timeout=DEADLINE)
        terminal.close()
        graph.shutdown()
