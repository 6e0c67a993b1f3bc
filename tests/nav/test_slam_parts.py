"""The parts of the gmapping node's mapper, each against what it must compute: plane motions,
the pose graph's solver and optimiser, the branch-and-bound search (against brute force), the
scan matcher, GMapping's occupancy counting, and the parameters' reading."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from belvedere.nav.slam import GMappingParams
from belvedere.nav.slam._grid import FieldGrid
from belvedere.nav.slam._match import refine
from belvedere.nav.slam._occupancy import OccupancyCounts
from belvedere.nav.slam._posegraph import PoseGraph, _solve_spd
from belvedere.nav.slam._se2 import between, compose, inverse, transform_points, wrap
from belvedere.nav.slam._search import SearchPyramid

Array = npt.NDArray[np.float64]


def _room_points(rng: np.random.Generator, count: int = 400) -> Array:
    """Points on the walls of a 6 m x 4 m room with a pillar and an alcove (no symmetry)."""
    segments = [
        ((-3, -2), (3, -2)),
        ((3, -2), (3, 2)),
        ((3, 2), (0.5, 2)),
        ((0.5, 2), (0.5, 2.6)),
        ((0.5, 2.6), (-1, 2.6)),
        ((-1, 2.6), (-1, 2)),
        ((-1, 2), (-3, 2)),
        ((-3, 2), (-3, -2)),
        ((1, -0.5), (1.4, -0.5)),
        ((1.4, -0.5), (1.4, -0.1)),
    ]
    pts = []
    for (x0, y0), (x1, y1) in segments:
        t = rng.uniform(0, 1, count // len(segments))
        pts.append(np.column_stack([x0 + t * (x1 - x0), y0 + t * (y1 - y0)]))
    return np.vstack(pts)


def test_plane_motions_compose_and_invert() -> None:
    rng = np.random.default_rng(1)
    a = rng.normal(size=(20, 3))
    b = rng.normal(size=(20, 3))
    assert np.allclose(compose(a, between(a, b)), compose(b, np.zeros(3)))
    assert np.allclose(compose(a, inverse(a))[:, :2], 0.0)
    assert np.allclose(wrap(compose(a, inverse(a))[:, 2]), 0.0)
    p = rng.normal(size=(5, 2))
    back = transform_points(inverse(a[0]), transform_points(a[0], p))
    assert np.allclose(back, p)


def test_the_block_cholesky_solves_like_lapack() -> None:
    rng = np.random.default_rng(2)
    for n in (3, 96, 201):
        m = rng.normal(size=(n, n))
        a = m @ m.T + n * np.eye(n)
        b = rng.normal(size=n)
        x = _solve_spd(a, b)
        assert x is not None
        assert np.allclose(x, np.linalg.solve(a, b))
    assert _solve_spd(-np.eye(6), np.ones(6)) is None  # not positive definite


def test_the_pose_graph_spreads_a_loop_closure_over_the_loop() -> None:
    # a square of side 4 walked in 16 steps, the odometry turning 2 % too far
    truth = []
    pose = np.zeros(3)
    for k in range(16):
        truth.append(pose.copy())
        step = np.array([1.0, 0.0, math.pi / 2 if k % 4 == 3 else 0.0])
        pose = compose(pose, step)
    graph = PoseGraph()
    est = np.zeros(3)
    info = np.diag([100.0, 100.0, 400.0])
    for k in range(16):
        graph.add_node(est)
        if k + 1 < 16:
            z = between(truth[k], truth[k + 1])
            z[2] *= 1.02
            est = compose(est, z)
            graph.add_edge(k, k + 1, z, info)
    # the loop: the last pose seen from the first, exactly, with a strong edge
    graph.add_edge(0, 15, between(truth[0], truth[15]), np.diag([1e4, 1e4, 1e4]))
    before = np.hypot(*(graph.poses[15, :2] - truth[15][:2]))
    graph.optimize(iterations=10)
    after = np.abs(graph.poses[:, :2] - np.array(truth)[:, :2]).max()
    assert before > 0.1
    assert after < 0.05
    assert graph.errors()[-1] < 1.0
    assert np.isinf(graph.distances(0)).sum() == 0
    assert graph.distances(0)[15] == pytest.approx(1.0)  # the loop edge's own length


def test_branch_and_bound_finds_what_brute_force_finds() -> None:
    rng = np.random.default_rng(3)
    room = _room_points(rng)
    grid = FieldGrid(0.05, 0.05, 3)
    grid.insert(room)
    grid.finish()
    pyramid = SearchPyramid(grid, 4)
    level0 = pyramid.levels[0]
    for _ in range(4):
        scan = room[rng.choice(len(room), 60, replace=False)] + rng.normal(0, 0.01, (60, 2))
        center = np.array([*rng.normal(0, 0.1, 2), rng.normal(0, 0.03)])
        window, turn, step = 0.4, 0.05, 0.01
        found = pyramid.search(scan, center, window, turn, step, 0.0)
        assert found is not None
        half = math.ceil(window / 0.05)
        best = -1.0
        for a in center[2] + np.arange(-5, 6) * step:
            c, s = math.cos(a), math.sin(a)
            qx = (c * scan[:, 0] - s * scan[:, 1] + center[0] - pyramid.origin[0]) / 0.05 - half
            qy = (s * scan[:, 0] + c * scan[:, 1] + center[1] - pyramid.origin[1]) / 0.05 - half
            cx, cy = np.floor(qx).astype(int), np.floor(qy).astype(int)
            for ox in range(2 * half + 1):
                for oy in range(2 * half + 1):
                    x, y = cx + ox, cy + oy
                    ok = (x >= 0) & (y >= 0) & (x < level0.shape[1]) & (y < level0.shape[0])
                    best = max(best, float(np.where(ok, level0[y * ok, x * ok], 0).mean()))
        assert found.score == pytest.approx(best)
        # the true pose (the identity) is on the lattice's best cell
        assert np.hypot(*found.pose[:2]) < 0.06
        assert abs(found.pose[2]) < 0.011


def test_the_ambiguity_test_sees_a_corridors_second_fit() -> None:
    # two long parallel walls: every shift along them fits as well
    x = np.linspace(-4, 4, 400)
    walls = np.vstack(
        [np.column_stack([x, np.full_like(x, 1.0)]), np.column_stack([x, -np.ones_like(x)])]
    )
    grid = FieldGrid(0.05, 0.05, 3)
    grid.insert(walls)
    grid.finish()
    scan = walls[::8][np.abs(walls[::8, 0]) < 2]
    found = SearchPyramid(grid, 4).search(scan, np.zeros(3), 1.0, 0.02, 0.01, 0.3, ambiguity=0.8)
    assert found is not None
    assert found.runner_up > 0.8 * found.score


def test_the_matcher_recovers_a_displaced_pose() -> None:
    rng = np.random.default_rng(4)
    room = _room_points(rng, 800)
    grid = FieldGrid(0.05, 0.05, 3)
    grid.insert(room)
    truth = np.array([0.3, -0.2, 0.1])
    scan = transform_points(inverse(truth), room[::3]) + rng.normal(0, 0.005, (len(room[::3]), 2))
    start = truth + np.array([0.03, -0.02, 0.008])  # within the field's reach (3 cells)
    match = refine(grid, scan, start, iterations=20)
    # the walls lie on cell boundaries: the field follows the points, not the cells
    assert np.hypot(*(match.pose[:2] - truth[:2])) < 0.01
    assert abs(match.pose[2] - truth[2]) < 0.003
    assert match.score > 0.75
    # a strong prior holds the pose where the prior is
    held = refine(grid, scan, start, start, np.array([1e9, 1e9, 1e9]), iterations=20)
    assert np.allclose(held.pose, start, atol=1e-4)


def test_occupancy_counts_as_gmapping_does() -> None:
    counts = OccupancyCounts(0.1, -1.0, -1.0, 1.0, 1.0)
    sensors = np.array([[0.05, 0.05]])
    # one beam 0.5 m along +x hits; one along +y is cut at the usable range (no hit)
    ends = np.array([[0.55, 0.05], [0.05, 0.85]])
    counts.add_scans_indexed(sensors, np.array([0, 0]), ends, np.array([True, False]))
    grid = counts.to_map(0.25)
    origin = grid.origin

    def col(x: float) -> int:
        return math.floor((x - origin[0]) / 0.1)

    def row(y: float) -> int:
        return math.floor((y - origin[1]) / 0.1)

    assert grid.data[row(0.05), col(0.55)] == 100  # the end cell: hit
    assert all(grid.data[row(0.05), col(x)] == 0 for x in (0.05, 0.15, 0.25, 0.35, 0.45))
    assert grid.data[row(0.75), col(0.05)] == 0  # crossed
    assert grid.data[row(0.85), col(0.05)] == -1  # the cut beam's end is not seen
    assert grid.data[row(-0.5), col(-0.5)] == -1
    # it grows to hold a beam beyond the initial extent, keeping its cells
    counts.add_scans_indexed(sensors, np.array([0]), np.array([[2.55, 0.05]]), np.array([True]))
    bigger = counts.to_map(0.25)
    assert bigger.width > grid.width
    assert bigger.origin == grid.origin


def test_parameters_are_read_as_slam_gmapping_names_them() -> None:
    p = GMappingParams.from_mapping({"particles": "80", "delta": 0.1, "linearUpdate": 1, "x": 1})
    assert (p.particles, p.delta, p.linearUpdate, p.maxRange) == (80, 0.1, 1.0, None)
    assert GMappingParams().srr == 0.1
    assert GMappingParams().map_update_interval == 5.0
    with pytest.raises(ValueError, match="parameter particles: expected a whole number"):
        GMappingParams.from_mapping({"particles": 2.5})
    with pytest.raises(ValueError, match="parameter delta must be positive"):
        GMappingParams.from_mapping({"delta": 0})
    with pytest.raises(ValueError, match="the map's extent is empty"):
        GMappingParams.from_mapping({"xmin": 5, "xmax": 1})
