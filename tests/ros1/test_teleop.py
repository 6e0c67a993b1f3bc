"""The course's keyboard teleop (a Python 2 rospy script with CRLF line ends, reading raw keys
from its terminal) drives the kinematic and the physics simulation: keys typed into a real
pseudo-terminal, the robot's odometry watched from another process."""

from __future__ import annotations

import math
import os
import pty
import subprocess
import sys
import time
from typing import Any

import pytest

from belvedere.graph import Graph, ZenohTransport
from tests.conftest import EXAMPLES
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


def _type(fd: int, keys: str, seconds: float) -> None:
    """Press ``keys`` over and over for ``seconds`` (the teleop stops without a key)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        os.write(fd, keys.encode())
        time.sleep(0.1)


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
    main_fd, terminal = pty.openpty()
    teleop = None
    try:
        wait_until(lambda: poses, what=f"the {engine} simulation's /odom")
        teleop = subprocess.Popen(
            [*RUN, "mbot_teleop", "mbot_teleop.py", "_speed:=0.4"],
            stdin=terminal,
            stdout=terminal,
            stderr=subprocess.PIPE,
            text=True,
        )
        start = poses[-1]
        _type(main_fd, "i", 2.0)
        wait_until(lambda: poses[-1][0] - start[0] > 0.1, what="the robot to drive forward")
        turned_from = poses[-1]
        _type(main_fd, "j", 1.5)
        wait_until(lambda: abs(poses[-1][2] - turned_from[2]) > 0.3, what="the robot to turn left")
        os.write(main_fd, b"\x03")  # Ctrl-C, as a raw terminal passes it: the script quits
        assert teleop.wait(timeout=DEADLINE) == 0, teleop.stderr.read() if teleop.stderr else ""
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
        os.close(main_fd)
        os.close(terminal)
        watcher.shutdown()
        sim.terminate()
        sim.wait(timeout=DEADLINE)
