"""The course's fake TurtleBot (rbx1): the ArbotiX driver's diff_controller publishes its
wheels' states as ``base_l_wheel_joint`` and ``base_r_wheel_joint`` (arbotix_python's names),
which are the wheel joints of rbx1's TurtleBot: robot_state_publisher places the wheels and
has nothing to warn about, as in the course."""

from __future__ import annotations

import subprocess
import sys

import yaml

from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE

TURTLEBOT = str(EXAMPLES / "rbx1_description/urdf/turtlebot.urdf.xacro")
RBX1_YAML = str(EXAMPLES / "rbx1_bringup/config/fake_turtlebot_arbotix.yaml")


def test_the_fake_turtlebots_wheels_are_placed_without_a_warning(endpoint: str) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "belvedere", "sim", TURTLEBOT, "--config", RBX1_YAML,
         "--headless", "--rtf", "max", "--duration", "0.5", "--echo", "/tf"],
        capture_output=True, text=True, timeout=DEADLINE, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "not found in URDF" not in done.stderr
    children = {
        t["child_frame_id"]
        for d in yaml.safe_load_all(done.stdout)
        if d is not None
        for t in d["transforms"]
    }
    assert {"left_wheel_link", "right_wheel_link", "base_footprint"} <= children
