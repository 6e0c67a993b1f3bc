"""The local planners' grid maps against plain re-statements of base_local_planner's MapGrid
and the plan handling of its goal functions."""

from __future__ import annotations

from collections import deque

import numpy as np
import pytest

from belvedere.nav.costmap import INSCRIBED, LETHAL, NO_INFORMATION, CostGrid
from belvedere.nav.local._maps import (
    filled_footprint_cells,
    plan_cells,
    plan_in_window,
    prune_plan,
    wavefronts,
)
from tests.nav.local_world import SQUARE


def mapgrid(costs: np.ndarray, sources: list[tuple[int, int]]) -> np.ndarray:
    """MapGrid's computeTargetDistance, cell by cell with a queue."""
    h, w = costs.shape
    size = h * w
    dist = np.full((h, w), float(size + 1))
    marked = np.zeros((h, w), dtype=bool)
    queue: deque[tuple[int, int]] = deque()
    for i, j in sources:
        dist[j, i] = 0.0
        marked[j, i] = True
        queue.append((i, j))
    while queue:
        i, j = queue.popleft()
        for di, dj in ((-1, 0), (1, 0), (0, -1), (0, 1)):
            ni, nj = i + di, j + dj
            if not (0 <= ni < w and 0 <= nj < h) or marked[nj, ni]:
                continue
            if costs[nj, ni] >= INSCRIBED:
                dist[nj, ni] = float(size)
                continue
            dist[nj, ni] = min(dist[nj, ni], dist[j, i] + 1)
            marked[nj, ni] = True
            queue.append((ni, nj))
    return dist


@pytest.mark.parametrize("seed", range(6))
def test_wavefronts_match_mapgrid(seed: int) -> None:
    rng = np.random.default_rng(seed)
    costs = rng.choice(
        np.array([0, 50, INSCRIBED, LETHAL, NO_INFORMATION], dtype=np.uint8),
        size=(23, 31),
        p=[0.6, 0.15, 0.1, 0.1, 0.05],
    )
    grid = CostGrid(costs, 0.1)
    many = [(int(rng.integers(31)), int(rng.integers(23))) for _ in range(12)]
    one = [(int(rng.integers(31)), int(rng.integers(23)))]
    sets = [(np.array([i for i, _ in s]), np.array([j for _, j in s])) for s in (many, one)]
    for got, sources in zip(wavefronts(grid, sets), (many, one), strict=True):
        assert np.array_equal(got.dist, mapgrid(costs, sources))


def test_the_robots_cells_let_the_wave_through() -> None:
    costs = np.zeros((10, 10), dtype=np.uint8)
    costs[:, 5] = INSCRIBED
    grid = CostGrid(costs, 0.1)
    passable = np.zeros((10, 10), dtype=bool)
    passable[4, 5] = True
    blocked, through = (
        wavefronts(grid, [(np.array([0]), np.array([4]))], passable=p)[0].dist
        for p in (None, passable)
    )
    assert blocked[4, 9] == 101.0  # unreachable
    assert through[4, 9] == 9.0


def test_plan_cells_stop_where_the_plan_leaves_the_grid() -> None:
    costs = np.zeros((10, 10), dtype=np.uint8)
    costs[5, 3] = NO_INFORMATION
    grid = CostGrid(costs, 0.1, origin_x=0.0, origin_y=0.0)
    plan = np.array([[-0.5, 0.05], [0.55, 0.05], [0.55, 2.0], [0.05, 0.05]])
    columns, rows = plan_cells(grid, plan)
    # from the first cell inside along y = 0.05, up x = 0.55 to the top edge, and no further
    assert (columns[0], rows[0]) == (0, 0)
    assert (columns[-1], rows[-1]) == (5, 9)
    assert set(zip(columns.tolist(), rows.tolist(), strict=True)) >= {(5, 5), (3, 0)}
    # an unknown cell ends the run too
    columns, _ = plan_cells(grid, np.array([[0.05, 0.55], [0.95, 0.55]]))
    assert columns.tolist() == [0, 1, 2]


def test_plan_window_and_pruning() -> None:
    grid = CostGrid(np.zeros((40, 40), dtype=np.uint8), 0.05)  # 2 m: a 1 m reach
    xs = np.arange(0.0, 5.0, 0.1)
    plan = np.column_stack([xs, np.zeros_like(xs), np.zeros_like(xs)])
    window = plan_in_window(plan, grid, 1.5, 0.0)
    assert window[0, 0] == pytest.approx(0.5)
    assert window[-1, 0] == pytest.approx(2.5)
    # poses more than 1 m behind go
    assert prune_plan(plan, 2.05, 0.0) == 11
    assert prune_plan(plan, 20.0, 0.0) == len(plan)


def test_the_footprints_own_cells() -> None:
    grid = CostGrid(np.zeros((20, 20), dtype=np.uint8), 0.05)
    mask = filled_footprint_cells(grid, 0.5, 0.5, 0.0, SQUARE)
    assert mask.sum() == 36  # 0.3 m square: 6 x 6 cell centres
    assert mask[10, 10]
    assert not mask[10, 17]
