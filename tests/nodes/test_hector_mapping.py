"""hector_mapping in the course's hector_demo.launch: the physics simulation of the mbot in
the cloister, driven straight; the node maps, tracks the robot and publishes map → odom."""

from __future__ import annotations

import math
from typing import Any

import pytest
import yaml

from belvedere.cli import main
from tests.conftest import EXAMPLES

DEMO = str(EXAMPLES / "mbot_navigation/launch/hector_demo.launch")
FORWARD = "/cmd_vel geometry_msgs/Twist {linear: {x: 0.3}}"


def _documents(text: str) -> list[Any]:
    return [yaml.safe_load(d) for d in text.split("\n---\n") if d.strip()]


def _seconds(stamp: Any) -> float:
    return float(stamp["secs"]) + float(stamp["nsecs"]) / 1e9


def test_hector_demo_maps_and_tracks_the_robot(
    endpoint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    args = ["launch", DEMO, "--headless", "--rtf", "max", "--duration", "8", "--pub", FORWARD]
    args += ["--echo", "/slam_out_pose", "--echo", "/odom", "--echo", "/map_metadata"]
    assert main(args) == 0
    docs = [d for d in _documents(capsys.readouterr().out) if isinstance(d, dict)]
    poses = [d for d in docs if d.get("header", {}).get("frame_id") == "map"]
    odom = [d for d in docs if "child_frame_id" in d]
    meta = [d for d in docs if "resolution" in d]
    assert meta
    assert meta[-1]["resolution"] == pytest.approx(0.05)
    assert meta[-1]["width"] == meta[-1]["height"] == 512
    assert len(poses) > 20
    first = odom[0]["pose"]["pose"]["position"]
    for pose in poses[5::10]:
        stamp = _seconds(pose["header"]["stamp"])
        near = min(odom, key=lambda o: abs(_seconds(o["header"]["stamp"]) - stamp))
        truth = near["pose"]["pose"]["position"]
        est = pose["pose"]["position"]
        moved = (truth["x"] - first["x"], truth["y"] - first["y"])
        assert math.hypot(est["x"] - moved[0], est["y"] - moved[1]) < 0.05
    assert poses[-1]["pose"]["position"]["x"] > 1.5
