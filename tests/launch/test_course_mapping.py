"""The course's mapping step end to end, as a learner does it in three terminals: the physics
simulation with slam_gmapping (``belvedere launch mbot_navigation gmapping_demo.launch``), the
course's keyboard teleop driving the robot down the cloister's south walk, and ``map_saver``
writing the map — whose walls must be where the world's are, within two cells."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np

from belvedere.graph import Graph, ZenohTransport
from belvedere.maps import OCCUPIED, load_map
from tests.conftest import EXAMPLES
from tests.terminal import Terminal
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]
PACKAGES = ["--package-path", str(EXAMPLES)]


def _walls_found(grid: Any, y: float, xs: np.ndarray[Any, Any]) -> float:
    """The share of points (x, y) of a wall's face with an occupied cell within two cells."""
    res = grid.resolution
    found = 0
    for x in xs:
        col = math.floor((x - grid.origin[0]) / res)
        row = math.floor((y - grid.origin[1]) / res)
        found += bool((grid.data[row - 2 : row + 3, col - 2 : col + 3] == OCCUPIED).any())
    return found / len(xs)


def test_map_the_south_walk_with_the_teleop_and_save_it(endpoint: str, tmp_path: Path) -> None:
    launch = subprocess.Popen(
        [*BELVEDERE, "launch", *PACKAGES, "mbot_navigation", "gmapping_demo.launch", "--headless"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    watcher = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    xs: list[float] = []
    maps: list[int] = []
    node = watcher.create_node("watcher")
    node.subscribe("/odom", "nav_msgs/Odometry", lambda m: xs.append(m.pose.pose.position.x))
    node.subscribe("/map", "nav_msgs/OccupancyGrid", lambda m: maps.append(m.header.stamp.sec))
    watcher.start(rtf=None)
    terminal = Terminal()
    teleop = None
    try:
        wait_until(lambda: xs, what="the simulation's /odom")
        teleop = subprocess.Popen(
            [*BELVEDERE, "run", *PACKAGES, "mbot_teleop", "mbot_teleop.py", "_speed:=0.5"],
            stdin=terminal.slave,
            stdout=terminal.slave,
            stderr=subprocess.DEVNULL,
        )
        terminal.wait_for("currently:")
        start = xs[-1]
        terminal.press_until("i", lambda: xs[-1] - start > 4.0, "the robot to drive 4 m")
        # slam_gmapping publishes a map once map_update_interval (5 s) passed and a scan was
        # added (after linearUpdate or angularUpdate of motion): turn on the spot until then
        driven = len(maps)
        terminal.press_until("j", lambda: len(maps) > driven, "a map after the drive")
        terminal.type("k")  # stop
        saver = subprocess.run(
            [*BELVEDERE, "run", *PACKAGES, "map_server", "map_saver", "-f", "cloister"],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=DEADLINE,
            check=False,
        )
        assert saver.returncode == 0, saver.stderr
    finally:
        if teleop is not None:
            teleop.kill()
            teleop.wait(timeout=DEADLINE)
        terminal.close()
        watcher.shutdown()
        launch.terminate()
        _, err = launch.communicate(timeout=DEADLINE)
    assert "error" not in err.lower(), err
    grid = load_map(tmp_path / "cloister.yaml")
    assert grid.resolution == 0.05
    # the south walk between the outer wall (its face at y = -6) and the garth's (y = -3),
    # seen from x = -1 to x = 5 (the robot started at x = 0 and drove 4 m east); the map
    # frame is the odometry's, which starts at the world's origin in this simulation
    seen = np.arange(-1.0, 5.0, grid.resolution)
    assert _walls_found(grid, -6.0, seen) > 0.9
    assert _walls_found(grid, -3.0, seen) > 0.75  # the colonnade hides some of it
    # nothing stands in the walk between the outer wall and the pillars (y = -3.5), and the
    # robot's line is free where it drove (behind its start the laser did not look)
    res, (ox, oy) = grid.resolution, grid.origin[:2]
    cols = slice(math.floor((-1.0 - ox) / res), math.floor((5.0 - ox) / res))
    walk = grid.data[math.floor((-5.85 - oy) / res) : math.floor((-3.75 - oy) / res), cols]
    assert (walk == OCCUPIED).sum() == 0
    along = slice(math.floor((0.5 - ox) / res), math.floor((4.0 - ox) / res))
    line = grid.data[math.floor((-4.5 - oy) / res), along]
    assert (line == 0).mean() > 0.8  # the first metre has a few unknown cells
    assert (line != OCCUPIED).all()
