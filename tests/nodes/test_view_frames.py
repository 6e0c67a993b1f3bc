"""``belvedere run tf view_frames`` beside the course's ArbotiX launch: ``frames.gv`` and
``frames.pdf`` in the working directory, with every frame of the robot and tf2's edge labels."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from belvedere.description.urdf import RobotModel
from tests.processes import BelvedereProcess
from tests.waiting import DEADLINE

LAUNCH = Path(__file__).parents[2] / "examples" / "mbot_description" / "launch"
ROBOT = LAUNCH.parent / "urdf" / "xacro" / "gazebo" / "mbot_with_camera_gazebo.xacro"


def test_view_frames_writes_the_robots_tree(endpoint: str, tmp_path: Path) -> None:
    del endpoint
    if shutil.which("dot") is None:
        pytest.skip("Graphviz's dot is not installed")
    launch = BelvedereProcess(
        ["launch", "--headless", str(LAUNCH / "arbotix_mbot_with_camera_xacro.launch")],
        ready="process[rviz",
        ended="the ArbotiX launch ended",
    )
    try:
        ran = subprocess.run(
            [sys.executable, "-m", "belvedere", "run", "tf", "view_frames"],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=DEADLINE,
            check=False,
        )
    finally:
        launch.stop()
    assert ran.returncode == 0, ran.stderr
    assert "frames.pdf generated" in ran.stdout
    gv = (tmp_path / "frames.gv").read_text()
    assert (tmp_path / "frames.pdf").read_bytes().startswith(b"%PDF")
    for link in RobotModel.from_path(ROBOT).links:
        assert f'"{link.name}"' in gv, link.name
    assert '"odom" -> "base_footprint"' in gv
    assert "Broadcaster: /robot_state_publisher" in gv
    assert "Average rate:" in gv
    assert "Buffer length:" in gv
