"""The gmapping node's mapper on data from belvedere's physics simulation: the mbot driven once
around the cloister and on past its start, with drifting odometry (see ``simulated``).

Scored against the simulation's true pose: the mapper's relative motions must be many times
more accurate than the odometry's, its map's walls where the world's are, and the same input
must give the same bytes out — through the library and through ``belvedere slam`` on a bag.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from belvedere.cli import main
from belvedere.maps import OCCUPIED, load_map, read_tum
from belvedere.nav.slam import GMappingParams, SubmapSlam
from tests.nav import simulated
from tests.nav.simulated import Recording

# The course's gmapping.launch for the mbot (examples/mbot_navigation/launch).
PARAMS = {
    "maxRange": 6.0,
    "maxUrange": 5.5,
    "linearUpdate": 0.5,
    "angularUpdate": 0.436,
    "minimumScore": 50,
    "xmin": -10.0,
    "ymin": -10.0,
    "xmax": 10.0,
    "ymax": 10.0,
}


@pytest.fixture(scope="module")
def recording() -> Recording:
    return simulated.record()


@pytest.fixture(scope="module")
def bag(recording: Recording, tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("bag") / "cloister.bag"
    simulated.write_bag(path, recording)
    return path


def _slam(rec: Recording) -> SubmapSlam:
    laser = simulated.laser_of(rec)
    slam = SubmapSlam(laser, GMappingParams.from_mapping(PARAMS))
    for ns, scan, odom in zip(rec.stamps_ns, rec.scans, rec.odom, strict=True):
        slam.add_scan(ns / 1e9, np.asarray(scan.ranges), odom)
    return slam


def test_the_run_closes_the_loop_with_drifting_odometry(recording: Recording) -> None:
    truth = recording.truth
    assert len(recording.scans) > 300
    assert np.hypot(*(truth[-1, :2] - truth[0, :2])) < 2.0  # back where it began
    assert abs(truth[-1, 2] - truth[0, 2] - 2 * math.pi) < 0.3  # one turn around
    odom_xy, odom_yaw = simulated.errors(recording.odom, truth)
    assert odom_xy > 0.3  # the odometry alone is far off: metres at the loop's end
    assert odom_yaw > math.radians(3)


def test_slam_is_many_times_more_accurate_than_the_odometry(recording: Recording) -> None:
    slam = _slam(recording)
    _, poses = slam.trajectory()
    assert len(poses) == len(recording.scans)  # one pose per scan
    xy, yaw = simulated.errors(poses, recording.truth)
    odom_xy, odom_yaw = simulated.errors(recording.odom, recording.truth)
    assert xy < 0.08
    assert xy < odom_xy / 5
    assert yaw < math.radians(1)
    assert yaw < odom_yaw / 5
    # where the map frame starts: at the odometry's first pose, which was the true one
    assert np.hypot(*(poses[-1, :2] - recording.truth[-1, :2])) < 0.15


def test_slam_gives_the_same_output_for_the_same_input(recording: Recording) -> None:
    a, b = _slam(recording), _slam(recording)
    assert np.array_equal(a.trajectory()[1], b.trajectory()[1])
    assert np.array_equal(a.occupancy().data, b.occupancy().data)


def _wall_cells(grid_data: np.ndarray, origin: tuple[float, float], res: float) -> float:
    """The share of the world's outer south wall's inner face (y = -6, x in [-6, 6]) that
    has an occupied cell within two cells of it."""
    found = 0
    xs = np.arange(-6.0, 6.0, res)
    for x in xs:
        col = math.floor((x - origin[0]) / res)
        row = math.floor((-6.0 - origin[1]) / res)
        patch = grid_data[row - 2 : row + 3, col - 2 : col + 3]
        found += bool((patch == OCCUPIED).any())
    return found / len(xs)


def test_belvedere_slam_over_a_bag(
    bag: Path, recording: Recording, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    args = [str(f"{k}:={v}") for k, v in PARAMS.items()]
    outputs = []
    for run in ("a", "b"):
        (tmp_path / run).mkdir()
        monkeypatch.chdir(tmp_path / run)
        command = ["slam", str(bag), "--trajectory", "run.tum", "-o", "map"]
        assert main([*command, "--base-frame", "base_footprint", *args]) == 0
        outputs.append([Path(name).read_bytes() for name in ("run.tum", "map.pgm", "map.yaml")])
    assert outputs[0] == outputs[1]  # deterministic, to the byte
    rows = read_tum(tmp_path / "a/run.tum")
    assert len(rows) == len(recording.scans)
    assert rows[0, 0] == pytest.approx(recording.stamps_ns[0] / 1e9)
    yaw = 2 * np.arctan2(rows[:, 6], rows[:, 7])
    poses = np.column_stack([rows[:, 1], rows[:, 2], np.unwrap(yaw)])
    xy, _ = simulated.errors(poses, recording.truth)
    assert xy < 0.08
    grid = load_map(tmp_path / "a/map.yaml")
    assert grid.resolution == pytest.approx(0.05)
    assert grid.origin[:2] == (-10.0, -10.0)  # xmin, ymin
    assert _wall_cells(grid.data, grid.origin[:2], grid.resolution) > 0.9


def test_belvedere_slam_explains_bad_input(
    bag: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = ["--trajectory", str(tmp_path / "t.tum")]
    assert main(["slam", str(tmp_path / "missing.bag"), *out]) == 1
    assert "missing.bag: no such bag" in capsys.readouterr().err
    assert main(["slam", str(bag), *out, "partcles:=30"]) == 1
    err = capsys.readouterr().err
    assert "unknown parameter 'partcles'" in err
    assert "particles" in err
    assert main(["slam", str(bag), *out, "delta:=fine"]) == 1
    assert "parameter delta: expected a number, got 'fine'" in capsys.readouterr().err
    assert main(["slam", str(bag), *out, "--scan-topic", "/laser"]) == 1
    assert "the bag has no topic /laser" in capsys.readouterr().err
    assert main(["slam", str(bag), *out]) == 1  # the base is base_footprint, not base_link
    assert "no scan on /scan could be placed" in capsys.readouterr().err
    assert main(["slam", str(bag)]) == 1
    assert "nothing to write" in capsys.readouterr().err
