"""hector's scan matcher on scans ray-cast in a known room: it tracks the true pose without
odometry, and its map has the walls where they are."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from belvedere.cli import main
from belvedere.graph import NS
from belvedere.maps import OCCUPIED, load_map, read_tum
from belvedere.msgs import message_from_data
from belvedere.nav.slam import HectorParams, HectorSlam
from tests.nav import simulated
from tests.nav.raycast import cast
from tests.nav.simulated import Recording

Array = npt.NDArray[np.float64]


def _rectangle(x0: float, y0: float, x1: float, y1: float) -> list[list[list[float]]]:
    corners = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    return [[corners[i], corners[(i + 1) % 4]] for i in range(4)]


WALLS = np.array(
    _rectangle(-5, -4, 5, 4)  # the room
    + _rectangle(-2, -1.5, 2, 1.5)  # a block in its middle: a loop corridor around it
    + _rectangle(3.5, 2.5, 3.9, 2.9)
    + _rectangle(-4, -3, -3.6, -2.6)
)
ANGLES = np.linspace(-math.pi, math.pi, 360, endpoint=False)


def _scan(pose: tuple[float, float, float], max_range: float = 6.0) -> Array:
    """Ranges from ``pose`` to the walls (inf beyond ``max_range``)."""
    x, y, yaw = pose
    r = cast(x, y, ANGLES + yaw, WALLS)
    return np.where(r < max_range, r, np.inf)


def _loop(steps: int) -> list[tuple[float, float, float]]:
    """An ellipse around the block, facing along it."""
    path = []
    for k in range(steps):
        s = k / steps * 2 * math.pi
        heading = math.atan2(2.75 * math.cos(s), -3.5 * math.sin(s))
        path.append((3.5 * math.cos(s), 2.75 * math.sin(s), heading))
    return path


def _run(seed: int) -> tuple[HectorSlam, list[float], list[float]]:
    rng = np.random.default_rng(seed)
    params = HectorParams(
        resolution=0.05, size=512, levels=3, laser_min=0.15, laser_max=6.0, angle_thresh=0.06
    )
    slam = HectorSlam(params)
    path = _loop(300)
    start = np.array(path[0])
    errors, headings = [], []
    for pose in path:
        ranges = _scan(pose) + rng.normal(0.0, 0.01, len(ANGLES))
        ok = np.isfinite(ranges) & (ranges > params.laser_min)
        points = np.column_stack((ranges[ok] * np.cos(ANGLES[ok]), ranges[ok] * np.sin(ANGLES[ok])))
        est = slam.process(points)
        # the map frame starts at the first pose: compare in the start's frame
        c, s = math.cos(start[2]), math.sin(start[2])
        dx, dy = pose[0] - start[0], pose[1] - start[1]
        truth = (c * dx + s * dy, -s * dx + c * dy, pose[2] - start[2])
        errors.append(math.hypot(est[0] - truth[0], est[1] - truth[1]))
        headings.append(abs((est[2] - truth[2] + math.pi) % (2 * math.pi) - math.pi))
    return slam, errors, headings


def test_it_tracks_a_loop_without_odometry() -> None:
    slam, errors, headings = _run(seed=1)
    assert max(errors) < 0.08  # metres, over a 20 m loop at 7 cm per scan
    assert float(np.mean(errors)) < 0.05
    assert max(headings) < math.radians(2)
    # the map: the room's far wall (x = 5 in the world) is occupied, the corridor is free
    grid = slam.map
    probability = grid.probability()
    start = _loop(300)[0]  # (3.5, 0, pi/2): the world's x = 5 wall is 1.5 m to the robot's right
    wall = grid.to_cells(np.array([[0.0, -1.5]]))[0].astype(int)
    corridor = grid.to_cells(np.array([[0.0, -0.75]]))[0].astype(int)
    assert start[0] == 3.5
    assert probability[wall[1], wall[0]] > 0.5 or probability[wall[1], wall[0] - 1] > 0.5
    assert probability[corridor[1], corridor[0]] < 0.5


def test_it_is_deterministic() -> None:
    a, errors_a, _ = _run(seed=3)
    b, errors_b, _ = _run(seed=3)
    assert errors_a == errors_b
    assert np.array_equal(a.map.cells, b.map.cells)


def _bag(path: Path) -> Recording:
    """The loop's scans as a bag (the laser at the base's centre; the odometry's TF, unused by
    hector, as the truth)."""
    path_poses = np.array(_loop(300))
    stamps = [(1000 + k) * NS // 10 for k in range(len(path_poses))]  # 10 Hz
    scans = [
        message_from_data(
            "sensor_msgs/LaserScan",
            {
                "header": {
                    "stamp": {"sec": ns // NS, "nanosec": ns % NS},
                    "frame_id": "laser_link",
                },
                "angle_min": float(ANGLES[0]),
                "angle_max": float(ANGLES[-1]),
                "angle_increment": float(ANGLES[1] - ANGLES[0]),
                "range_min": 0.15,
                "range_max": 6.0,
                "ranges": _scan(tuple(pose)).tolist(),
            },
        )
        for ns, pose in zip(stamps, path_poses, strict=True)
    ]
    rec = Recording(stamps, scans, path_poses, path_poses, (0.0, 0.0, 0.0))
    simulated.write_bag(path, rec)
    return rec


def test_belvedere_slam_with_hector_over_a_bag(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    rec = _bag(tmp_path / "room.bag")
    monkeypatch.chdir(tmp_path)
    command = ["slam", "room.bag", "--algorithm", "hector", "--base-frame", "base_footprint"]
    outputs = ["--trajectory", "run.tum", "-o", "map"]
    params = ["map_resolution:=0.05", "map_size:=512", "laser_min_dist:=0.15"]
    assert main([*command, *outputs, *params, "map_update_angle_thresh:=0.06"]) == 0
    rows = read_tum(tmp_path / "run.tum")
    assert len(rows) == len(rec.scans)
    yaw = 2 * np.arctan2(rows[:, 6], rows[:, 7])
    poses = np.column_stack([rows[:, 1], rows[:, 2], np.unwrap(yaw)])
    xy, turn = simulated.errors(poses, rec.truth)
    assert xy < 0.05
    assert turn < math.radians(1)
    grid = load_map(tmp_path / "map.yaml")
    assert grid.resolution == pytest.approx(0.05)
    # the map frame starts at the first pose (3.5, 0, pi/2): the world's x = 5 wall is at
    # the map's y = -1.5
    row = math.floor((-1.5 - grid.origin[1]) / grid.resolution)
    col = math.floor((0.0 - grid.origin[0]) / grid.resolution)
    assert (grid.data[row - 1 : row + 2, col] == OCCUPIED).any()
    assert main([*command, *outputs, "map_size:=big"]) == 1
    assert main([*command, *outputs, "partcles:=30"]) == 1
