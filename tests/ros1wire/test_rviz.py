"""Debian's rviz 1.14 on belvedere's physics simulation through ``belvedere roscore``, with no
other bridge: the course's laser mbot in Gazebo's world, rviz's RobotModel (from the
graph's ``robot_description``, placed by its TF) and its LaserScan drawn."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from belvedere.graph import graph_running
from tests.conftest import free_port
from tests.ros1wire.conftest import Ros1, ros_env
from tests.viewer.rviz_oracle import missing_rviz
from tests.viewer.rviz_pair import CONFIG, LAUNCH, _process, _rviz_shot
from tests.waiting import DEADLINE, wait_until


def test_rviz_shows_the_simulated_robot_and_its_scan(endpoint: str, tmp_path: Path) -> None:
    why = missing_rviz()
    if why:
        pytest.skip(why)
    config = tmp_path / "mbot.rviz"
    config.write_text(CONFIG)
    (tmp_path / "home").mkdir()
    launch = [sys.executable, "-m", "belvedere", "launch", "--headless", str(LAUNCH)]
    port = free_port()
    uri = f"http://127.0.0.1:{port}/"
    with _process(launch, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL):
        wait_until(lambda: graph_running(endpoint), what="the simulation's graph")
        roscore = [sys.executable, "-m", "belvedere", "roscore", "-p", str(port)]
        with _process(roscore, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL):
            ros = Ros1(uri)
            wait_until(
                lambda: "/scan" in ros.run("rostopic", "list").stdout.split(),
                what="the simulation's /scan listed by rostopic",
                timeout=DEADLINE,
            )
            shot = tmp_path / "rviz.png"
            _rviz_shot(config, {**os.environ, **ros_env(uri)}, 15.0, shot)
    view = np.asarray(Image.open(shot).convert("RGB")).astype(int)[70:-40, 20:-20]
    r, g, b = view[..., 0], view[..., 1], view[..., 2]
    laser = (r > 170) & (r - g > 80) & (r - b > 100)  # the scan's red squares
    colours, counts = np.unique(view.reshape(-1, 3), axis=0, return_counts=True)
    background = (view == colours[counts.argmax()]).all(axis=2)
    assert laser.sum() > 300, "rviz drew no laser points"
    assert (~background & ~laser).sum() > 5000, "rviz drew no robot model or grid"
