"""The course's keyboard teleop (a Python 2 rospy script with CRLF line ends, reading raw keys
from its terminal) drives the kinematic and the physics simulation: keys typed into a real
pseudo-terminal, the robot's odometry watched from another process."""

from __future__ import annotations

import math
import subprocess
import sys
from typing import Any

import pytest

from belvedere.graph import Graph, ZenohTransport
from tests.conftest import EXAMPLES
from tests.terminal import Terminal
from tests.waiting import DEADLINE, wait_until

TELEOP = EXAMPLES / "mbot_teleop/scripts/mbot_teleop.py"
MBOT = str(EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro")
MBOT_YAML = str(EXAMPLES / "mbot_description/config/fake_mbot_arbotix.yaml")
RUN = [sys.executable, "-m", "belvedere", "run", "--package-path", str(EXAMPLES)]
WORLD = str(EXAMPLES / "mbot_gazebo/worlds/playground.world")

ENGINES = {
    "kinematic": ["--engine", "kinematic", "--config", MBOT_YAML],
    "physics": ["--engine", "physics", "--world", WORLD],
}


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_the_course_teleop_drives_the_simulation(endpoint: str, engine: str) -> None:
    sim = subprocess.Popen(
        [sys.executable, "-m", "belvedere", "sim", MBOT, *ENGINES[engine], "--headless"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    watcher = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    poses: list[tuple[float, float, float]] = []

    def on_odom(msg: Any) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        poses.append((p.x, p.y, 2 * math.atan2(q.z, q.w)))

    watcher.create_node("watcher").subscribe("/odom", "nav_msgs/Odometry", on_odom)
    watcher.start(rtf=None)
    terminal = Terminal()
    teleop = None
    try:
        wait_until(lambda: poses, what=f"the {engine} simulation's /odom")
        teleop = subprocess.Popen(
            [*RUN, "mbot_teleop", "mbot_teleop.py", "_speed:=0.4"],
            stdin=terminal.slave,
            stdout=terminal.slave,
            stderr=subprocess.PIPE,
            text=True,
        )
        terminal.wait_for("currently:")
        start = poses[-1]
        terminal.press_until("i", lambda: poses[-1][0] - start[0] > 0.1, "the robot to drive")
        turned_from = poses[-1]
        terminal.press_until(
            "j", lambda: abs(poses[-1][2] - turned_from[2]) > 0.3, "the robot to turn"
        )
        # Ctrl-C as a raw terminal passes it: the script quits. (Typed in the instant the
        # script has its terminal cooked between two keys, the line discipline eats it, as a
        # real terminal would: press again.)
        terminal.press_until("\x03", lambda: teleop.poll() is not None, "the teleop to quit")
        assert teleop.wait(timeout=DEADLINE) == 0
        assert teleop.stderr is not None
        assert "a Python 2 script: running its Python 3 form" in teleop.stderr.read()
        # its last word is a zero Twist: the robot stops
        wait_until(
            lambda: len(poses) > 5 and abs(poses[-1][0] - poses[-5][0]) < 1e-3,
            what="the robot to stop",
        )
        assert poses[-1][2] > turned_from[2]  # j turns left (counter-clockwise)
    finally:
        if teleop is not None and teleop.poll() is None:
            teleop.kill()
        terminal.close()
        watcher.shutdown()
        sim.terminate()
        sim.wait(timeout=DEADLINE)
