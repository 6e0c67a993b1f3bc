"""Scans and odometry are data, not trusted geometry: ``belvedere slam`` over small bags of
hostile readings (odometry jumps to 1e7 m, 1e12 m and inf, NaN angles, range_max 1e30, 70,000
beams) ends with one warning or error naming the bag; the mapper's grids never pass
GRID_CELLS; the checks' counted warnings; and batching (for memory) changes no result."""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.bounded import GRID_CELLS, LimitError
from belvedere.cli import main
from belvedere.nav import _input
from belvedere.nav._input import Tally, grid_reach, pose_problem, scan_problem
from belvedere.nav.costmap import _layers
from belvedere.nav.costmap._grid import CostGrid
from belvedere.nav.costmap._layers import Observation, ObstacleLayer
from belvedere.nav.costmap._params import ObstacleParams, SourceParams
from belvedere.nav.slam import (
    GMappingParams,
    LaserGeometry,
    LogOddsGrid,
    SubmapSlam,
    _grid,
    _hector,
    _map,
)
from belvedere.nav.slam._grid import FieldGrid, FreeGrid, GridLimitError
from belvedere.nav.slam._occupancy import OccupancyCounts
from tests.nav import hostile
from tests.nav.hostile import Pose


def _stamp(msg: Any) -> int:
    return int(msg.header.stamp.sec) * 10**9 + int(msg.header.stamp.nanosec)


def _slam(
    bag: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], *args: str
) -> tuple[int, str]:
    out = ["--trajectory", str(tmp_path / "t.tum"), "-o", str(tmp_path / "map")]
    code = main(["-q", "slam", str(bag), *out, *args])
    return code, capsys.readouterr().err


def test_odometry_jumps_leave_the_map_bounded_with_one_warning_each(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    def jumps(i: int, pose: Pose, msg: Any) -> tuple[Pose, Any]:
        _, y, yaw = pose
        return {10: (1e7, y, yaw), 11: (1e12, y, yaw), 12: (math.inf, y, yaw)}.get(i, pose), msg

    bag = tmp_path / "jumps.bag"
    hostile.write_bag(bag, 30, jumps)
    code, err = _slam(bag, tmp_path, capsys, "linearUpdate:=0.25")
    assert code == 0
    assert err.splitlines() == [
        f"warning: {bag}: /scan: left 1 scan out of the map: a grid would grow past the cap "
        "of 33,554,432 cells (the first at 2.000 s: submap 0's grid to 1,648,603,635,163 "
        "cells)",
        f"warning: {bag}: /scan: skipped 1 scan: their odometry pose is more than 1e+08 m "
        "from the origin (the first at 2.100 s: (1e+12, 0.486065, 0.165))",
        f"warning: {bag}: /scan: skipped 1 scan: their odometry pose is not finite "
        "(the first at 2.200 s: (nan, nan, 0.18))",
    ]
    rows = np.loadtxt(tmp_path / "t.tum")
    assert len(rows) == 30 - 2
    assert rows[10, 1] == pytest.approx(1e7, rel=1e-6)  # matched there, not in the map
    assert np.abs(rows[11:, 1:3]).max() < 5
    grid = (tmp_path / "map.pgm").read_bytes()
    assert len(grid) < 4100 * 4100  # xmin..xmax, not grown to 1e7 m


def test_scans_the_mapper_cannot_use_are_skipped_with_one_warning_each(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    def scans(i: int, pose: Pose, msg: Any) -> tuple[Pose, Any]:
        ranges = np.array(msg.ranges)
        if i == 0:  # the first scan gives the laser's geometry: range_max 1e30 is clipped
            ranges[::30] = 1e7
            return pose, hostile.scan(_stamp(msg), ranges, range_max=1e30)
        if i in (3, 4):
            return pose, hostile.scan(_stamp(msg), ranges, increment=math.nan)
        if i == 5:
            return pose, hostile.scan(_stamp(msg), np.full(70_000, 2.0))
        if i in (6, 7):
            ranges[::2] = np.nan
            return pose, hostile.scan(_stamp(msg), ranges)
        return pose, msg

    bag = tmp_path / "scans.bag"
    hostile.write_bag(bag, 12, scans)
    code, err = _slam(bag, tmp_path, capsys)
    assert code == 0
    assert err.splitlines() == [
        f"warning: {bag}: /scan: uses ranges up to 144 m, the most a grid of 33,554,432 cells "
        "at 0.05 m holds around the laser (its range_max is 1e+30 m)",
        f"warning: {bag}: /scan: skipped 2 scans: their angle_increment is not finite "
        "(the first at 1.300 s: angle_increment nan)",
        f"warning: {bag}: /scan: skipped 1 scan: more than 65,536 beams "
        "(the first at 1.500 s: 70,000 beams)",
        f"warning: {bag}: /scan: dropped 360 NaN ranges in 2 scans",
    ]
    code, err = _slam(bag, tmp_path, capsys, "--algorithm", "hector")
    assert code == 0
    assert err.splitlines() == [
        f"warning: {bag}: /scan: skipped 2 scans: their angle_increment is not finite "
        "(the first at 1.300 s: angle_increment nan)",
        f"warning: {bag}: /scan: skipped 1 scan: more than 65,536 beams "
        "(the first at 1.500 s: 70,000 beams)",
        f"warning: {bag}: /scan: dropped 360 NaN ranges in 2 scans",
    ]


def test_when_every_scan_is_refused_the_error_says_why(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    def nan_increment(i: int, pose: Pose, msg: Any) -> tuple[Pose, Any]:
        return pose, hostile.scan(_stamp(msg), msg.ranges, increment=math.nan)

    bag = tmp_path / "nan.bag"
    hostile.write_bag(bag, 5, nan_increment)
    for algorithm in ("gmapping", "hector"):
        code, err = _slam(bag, tmp_path, capsys, "--algorithm", algorithm)
        assert code == 1
        assert err.splitlines() == [
            f"error: {bag}: no scan on /scan could be placed",
            "  hint: skipped 5 scans: their angle_increment is not finite "
            "(the first at 1.000 s: angle_increment nan)",
        ]


def test_a_keyframe_that_would_grow_a_grid_past_the_cap_is_left_out() -> None:
    laser = LaserGeometry.planar(-math.pi, 2 * math.pi / 360, 360, 0.1, 30.0, hostile.LASER)
    tally = Tally("test", logging.getLogger("test"), live=False)
    slam = SubmapSlam(laser, GMappingParams(linearUpdate=0.25), tally=tally)
    poses = hostile.path(12)
    for k, pose in enumerate(poses[:8]):
        assert (
            slam.add_scan(k * 0.1, hostile.room_ranges(pose).astype(np.float64), np.array(pose))
            is not None
        )
    before = slam.occupancy()
    keyframes = len(slam.keyframes)
    far = (3e7, 0.0, 0.0)  # a jump: the submap would span 30,000 km
    done = slam.add_scan(0.8, hostile.room_ranges(poses[8]).astype(np.float64), np.array(far))
    assert done is not None
    assert not done.keyframe
    assert len(slam.keyframes) == keyframes
    assert np.array_equal(slam.occupancy().data, before.data)  # the map so far, kept
    for k, pose in enumerate(poses[9:], start=9):
        slam.add_scan(k * 0.1, hostile.room_ranges(pose).astype(np.float64), np.array(pose))
    assert len(slam.keyframes) > keyframes
    assert tally.lines() == [
        "test: left 1 scan out of the map: a grid would grow past the cap of 33,554,432 "
        "cells (the first at 0.800 s: submap 0's grid to 250,956,135,097,980 cells)"
    ]
    for sub in slam.submaps:
        assert sub.grid.field.size <= GRID_CELLS


def test_grids_shed_their_margin_near_the_cap_and_refuse_past_it() -> None:
    grid = FieldGrid(0.05, 0.05, 3)
    side = 0.05 * math.isqrt(GRID_CELLS)
    layout = grid.layout(np.array([0.0, 0.0]), np.array([side - 1.0, 1.0]))
    assert layout is not None  # fits without its 10 m margin on the long side
    assert layout[1] * layout[2] <= GRID_CELLS
    with pytest.raises(GridLimitError, match=r"a grid of [\d,]+ cells, more than the cap"):
        grid.layout(np.array([0.0, 0.0]), np.array([side, side]))
    with pytest.raises(GridLimitError):
        FreeGrid(0.001).layout(np.array([0.0, 0.0]), np.array([math.inf, 1.0]))
    with pytest.raises(LimitError, match=r"a map of [\d,]+ cells, more than the cap"):
        OccupancyCounts(0.01, -100, -100, 100, 100)
    with pytest.raises(ValueError, match="a map of 64,000,000 cells, more than the cap"):
        GMappingParams.from_mapping({"xmin": -200, "xmax": 200, "ymin": -200, "ymax": 200})
    assert grid_reach(0.05, 5) == pytest.approx(0.05 * (2896 - 7))


def test_the_checks() -> None:
    assert scan_problem(360, -3.14, 0.0175, 0.1, 30.0) is None
    assert scan_problem(360, -3.14, 0.0175, 0.1, math.inf) is None  # no limit: REP 117
    assert scan_problem(65_537, 0.0, 1e-4, 0.1, 30.0) == (
        "more than 65,536 beams",
        "65,537 beams",
    )
    assert scan_problem(10, 0.0, 1e308, 0.1, 30.0) == (
        "their last beam's angle is not finite",
        "last beam's angle inf",
    )
    assert scan_problem(10, 0.0, 0.1, math.nan, 30.0) == (
        "their range_min is nan",
        "range_min nan",
    )
    assert scan_problem(10, 0.0, 0.1, 0.1, -math.inf) == (
        "their range_max is not above range_min and 0",
        "0.1 .. -inf",
    )
    assert pose_problem([1e7, -3.0, 0.5]) is None  # UTM coordinates are fine
    assert pose_problem([math.nan, 0.0, 0.0]) == ("not finite", "(nan, 0, 0)")
    assert pose_problem([0.0, -2e8, 0.0]) == (
        "more than 1e+08 m from the origin",
        "(0, -2e+08, 0)",
    )


def test_a_live_tally_logs_each_cause_at_1_10_100_and_the_report_once(
    caplog: pytest.LogCaptureFixture,
) -> None:
    log = logging.getLogger("belvedere.test")
    live = Tally("/node", log)
    quiet = Tally("bag: /scan", log, live=False)
    with caplog.at_level(logging.WARNING, logger="belvedere"):
        for k in range(120):
            for tally in (live, quiet):
                tally.add("dropped {items} in {count}", items=2, item="NaN range")
                tally.add("skipped {count}: odd {braces}", first=f"{k}.000 s: x")
        quiet.once("a note")
        quiet.once("a note")
        assert [r.getMessage() for r in caplog.records] == [
            "/node: dropped 2 NaN ranges in 1 scan",
            "/node: skipped 1 scan: odd {braces} (the first at 0.000 s: x)",
            "/node: dropped 20 NaN ranges in 10 scans so far",
            "/node: skipped 10 scans so far: odd {braces} (the first at 0.000 s: x)",
            "/node: dropped 200 NaN ranges in 100 scans so far",
            "/node: skipped 100 scans so far: odd {braces} (the first at 0.000 s: x)",
        ]
        caplog.clear()
        quiet.report()
        live.report()
        quiet.report()
        assert [r.getMessage() for r in caplog.records] == [
            "bag: /scan: dropped 240 NaN ranges in 120 scans",
            "bag: /scan: skipped 120 scans: odd {braces} (the first at 0.000 s: x)",
            "bag: /scan: a note",
            "/node: dropped 240 NaN ranges in 120 scans",
            "/node: skipped 120 scans: odd {braces} (the first at 0.000 s: x)",
        ]
    assert quiet.count("skipped {count}: odd {braces}") == 120
    assert _input.plural(1, "scan") == "1 scan"


def test_batches_for_memory_change_no_result(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(7)
    angles = np.linspace(-math.pi, math.pi, 3000, endpoint=False)
    r = 2.0 + 20.0 * rng.random(len(angles))
    ends = np.stack([r * np.cos(angles) + 0.3, r * np.sin(angles) - 0.2], axis=1)

    def free_counts() -> Any:
        grid = FreeGrid(0.2)
        grid.add_beams(np.array([0.3, -0.2]), ends, 0.4)
        grid.add_beams(np.array([1.0, 0.5]), ends * 0.5, 0.4)
        return grid.counts

    def hector_cells() -> Any:
        grid = LogOddsGrid(0.05, 300, (-7.5, -7.5))
        grid.update((0.3, -0.2), ends, -0.4, 0.9)
        grid.update((30.0, 40.0), ends, -0.4, 0.9)  # the sensor off the map
        return grid.cells

    def cleared() -> Any:
        source = SourceParams(
            "scan", "/scan", "", "LaserScan", 0.0, 0.0, 0.0, 2.0, 2.5, 1e9, True, True, False
        )
        layer = ObstacleLayer(ObstacleParams("obstacles", False, True, sources=(source,)))
        master = CostGrid(np.full((200, 200), 255, dtype=np.uint8), 0.05, -5.0, -5.0)
        layer.match(master)
        assert layer.grid is not None
        points = np.column_stack([ends, np.zeros(len(ends))])
        bounds = layer._clear(layer.grid, Observation(np.array([0.3, -0.2, 0]), points, 0), 1e9)
        return layer.grid.costs, bounds

    laser = LaserGeometry.planar(-math.pi, 2 * math.pi / 360, 360, 0.1, 30.0, hostile.LASER)

    def mapped() -> Any:
        slam = SubmapSlam(laser, GMappingParams(linearUpdate=0.1, xmin=-6, xmax=6, ymin=-6, ymax=6))
        for k, pose in enumerate(hostile.path(40)):
            slam.add_scan(k * 0.1, hostile.room_ranges(pose).astype(np.float64), np.array(pose))
        return slam.occupancy().data

    whole = free_counts(), hector_cells(), cleared(), mapped()
    monkeypatch.setattr(_grid, "_BATCH_SAMPLES", 1000)
    monkeypatch.setattr(_hector, "_BATCH_SAMPLES", 1000)
    monkeypatch.setattr(_layers, "_RAY_CELLS", 1000)
    monkeypatch.setattr(_map, "_TRACE_BEAMS", 1000)
    batched = free_counts(), hector_cells(), cleared(), mapped()
    assert np.array_equal(whole[0], batched[0])
    assert np.array_equal(whole[1], batched[1])
    assert np.array_equal(whole[2][0], batched[2][0])
    assert whole[2][1] == batched[2][1]
    # (the map grows by whole cells and a spare one each time: other batches, perhaps a
    # spare row or column of unknown cells more or less at the far edge — the same map)
    a, b = whole[3], batched[3]
    h, w = min(a.shape[0], b.shape[0]), min(a.shape[1], b.shape[1])
    assert np.array_equal(a[:h, :w], b[:h, :w])
    for grid in (a, b):
        assert (grid[h:] == -1).all()
        assert (grid[:, w:] == -1).all()
