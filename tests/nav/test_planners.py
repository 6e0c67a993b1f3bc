"""The global planners on hand-made grids: path lengths against a brute-force Dijkstra, lethal
and inscribed cells avoided, navfn's tolerance, unknown space, A* and grid paths, the
orientation modes, and the errors."""

from __future__ import annotations

import heapq
import math

import numpy as np
import numpy.typing as npt
import pytest

from belvedere.nav.costmap import FREE, INSCRIBED, LETHAL, NO_INFORMATION, CostGrid
from belvedere.nav.planners import (
    POT_HIGH,
    GlobalPlannerPlugin,
    NavfnPlanner,
    NoPathError,
    UnknownPluginError,
    make_global_planner,
)

RES = 0.1
PLANNERS = [
    ("navfn/NavfnROS", {}),
    ("global_planner/GlobalPlanner", {}),
    ("global_planner/GlobalPlanner", {"use_quadratic": False}),
    ("global_planner/GlobalPlanner", {"use_dijkstra": False}),
    ("global_planner/GlobalPlanner", {"use_grid_path": True}),
]


def _maze() -> npt.NDArray[np.uint8]:
    """60 x 60 cells of 0.1 m: two walls with gaps at opposite ends, a pillar."""
    costs = np.zeros((60, 60), dtype=np.uint8)
    costs[20, 0:48] = LETHAL
    costs[40, 12:60] = LETHAL
    costs[28:33, 25:30] = LETHAL
    return costs


def _shortest(costs: npt.NDArray[np.uint8], start: tuple[int, int], goal: tuple[int, int]) -> float:
    """Brute force: Dijkstra over 8-connected free cells, metres between cell centres."""
    height, width = costs.shape
    best = {start: 0.0}
    queue = [(0.0, start)]
    while queue:
        d, (i, j) = heapq.heappop(queue)
        if (i, j) == goal:
            return d * RES
        if d > best[(i, j)]:
            continue
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                n = (i + di, j + dj)
                if (
                    (di or dj)
                    and 0 <= n[0] < width
                    and 0 <= n[1] < height
                    and costs[n[1], n[0]] < INSCRIBED
                ):
                    nd = d + math.hypot(di, dj)
                    if nd < best.get(n, math.inf):
                        best[n] = nd
                        heapq.heappush(queue, (nd, n))
    return math.inf


def _length(path: npt.NDArray[np.float64]) -> float:
    return float(np.hypot(*np.diff(path[:, :2], axis=0).T).sum())


def _cells_of(grid: CostGrid, path: npt.NDArray[np.float64], corner: bool = False) -> list[int]:
    """The costs under the path's points (``corner``: navfn's points are at cell corners, so
    the cell a point belongs to is the nearest centre)."""
    shift = grid.resolution / 2 if corner else 0.0
    costs = []
    for x, y, _ in path[:-1]:
        cell = grid.world_to_map(x + shift, y + shift)
        assert cell is not None
        costs.append(int(grid.costs[cell[1], cell[0]]))
    return costs


@pytest.mark.parametrize(("plugin", "params"), PLANNERS)
def test_paths_are_near_the_shortest_and_stay_off_obstacles(
    plugin: str, params: dict[str, object]
) -> None:
    grid = CostGrid(_maze(), RES)
    planner = make_global_planner(plugin, params)
    start, goal = (1.05, 0.95, 0.0), (1.05, 5.05, 1.0)
    path = planner.plan(grid, start, goal)
    assert path[-1].tolist() == list(goal)
    assert np.hypot(*(path[0, :2] - start[:2])) < 0.1
    reference = _shortest(grid.costs, (10, 9), (10, 50))
    length = _length(path)
    # the 8-connected reference is at most 8% longer than the true shortest path; a grid
    # path (8 neighbours) is no shorter than it
    low = reference if params.get("use_grid_path") else reference / 1.09
    assert low - 0.15 <= length <= reference * 1.03 + 0.15
    assert max(_cells_of(grid, path, corner=plugin.startswith("navfn"))) < INSCRIBED


def test_inscribed_cells_are_walls_to_the_planners() -> None:
    costs = np.zeros((50, 50), dtype=np.uint8)  # navfn never enters its 7-cell frame
    costs[20, :] = INSCRIBED
    costs[20, 30] = 200  # a costly gap
    grid = CostGrid(costs, RES)
    for plugin, params in PLANNERS:
        path = make_global_planner(plugin, params).plan(grid, (1.0, 1.0, 0), (1.0, 3.5, 0))
        crossing = [c for c in _cells_of(grid, path, plugin.startswith("navfn")) if c > 0]
        assert crossing, plugin
        assert max(crossing) == 200, plugin
    costs[20, 30] = INSCRIBED
    for plugin, params in PLANNERS:
        with pytest.raises(NoPathError, match=r"no path from \(1\.00, 1\.00\) to \(1\.00, 3\.50\)"):
            make_global_planner(plugin, params).plan(grid, (1.0, 1.0, 0), (1.0, 3.5, 0))


def test_costs_steer_the_path_around_expensive_cells() -> None:
    costs = np.zeros((40, 60), dtype=np.uint8)
    costs[10:30, 25:35] = 250  # a costly block in the straight line
    grid = CostGrid(costs, RES)
    path = make_global_planner("navfn/NavfnROS", {}).plan(grid, (1.0, 2.0, 0), (5.0, 2.0, 0))
    assert max(_cells_of(grid, path, corner=True)) < 250
    assert _length(path) > 4.0


def test_navfn_tolerance_finds_the_nearest_reachable_point() -> None:
    costs = np.zeros((60, 60), dtype=np.uint8)
    costs[30:40, 30:40] = LETHAL
    grid = CostGrid(costs, RES)
    goal = (3.45, 3.45, 0.5)
    with pytest.raises(NoPathError):
        make_global_planner("navfn/NavfnROS", {}).plan(grid, (1.0, 1.0, 0), goal)
    planner = make_global_planner("navfn/NavfnROS", {"default_tolerance": 0.6})
    path = planner.plan(grid, (1.0, 1.0, 0), goal)
    end = path[-1]
    assert end[2] == 0.5
    cell = grid.world_to_map(end[0], end[1])
    assert cell is not None
    assert grid.costs[cell[1], cell[0]] == FREE
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) <= 0.6 * math.sqrt(2)
    # the nearest reachable point of the tolerance square is just outside the block
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) == pytest.approx(0.6, abs=0.11)
    # global_planner reads default_tolerance but does not use it, as in ROS Noetic
    with pytest.raises(NoPathError):
        make_global_planner("global_planner/GlobalPlanner", {"default_tolerance": 0.6}).plan(
            grid, (1.0, 1.0, 0), goal
        )


def test_allow_unknown_decides_whether_unknown_space_is_crossed() -> None:
    costs = np.zeros((40, 40), dtype=np.uint8)
    costs[18:22, :] = NO_INFORMATION
    grid = CostGrid(costs, RES)
    for plugin in ("navfn/NavfnROS", "global_planner/GlobalPlanner"):
        path = make_global_planner(plugin, {}).plan(grid, (2.0, 1.0, 0), (2.0, 3.0, 0))
        assert NO_INFORMATION in _cells_of(grid, path, plugin.startswith("navfn"))
        with pytest.raises(NoPathError):
            make_global_planner(plugin, {"allow_unknown": False}).plan(
                grid, (2.0, 1.0, 0), (2.0, 3.0, 0)
            )


def test_navfn_keeps_off_its_border_frame_and_off_map_poses_fail() -> None:
    grid = CostGrid(np.zeros((40, 40), dtype=np.uint8), RES, -2.0, -2.0)
    planner = make_global_planner("navfn/NavfnROS", {})
    assert isinstance(planner, NavfnPlanner)
    with pytest.raises(NoPathError):  # 0.5 m from the edge: within navfn's 7-cell frame
        planner.plan(grid, (0.0, 0.0, 0), (1.55, 1.55, 0))
    with pytest.raises(NoPathError, match=r"goal sent to the planner \(5\.00, 0\.00\) is off"):
        planner.plan(grid, (0.0, 0.0, 0), (5.0, 0.0, 0))
    with pytest.raises(NoPathError, match=r"robot's start position \(-3\.00, 0\.00\) is off"):
        planner.plan(grid, (-3.0, 0.0, 0), (1.0, 0.0, 0))
    assert planner.potential is not None


def test_points_sit_at_cell_corners_for_navfn_and_centres_for_global_planner() -> None:
    grid = CostGrid(np.zeros((40, 40), dtype=np.uint8), RES)
    grid_path = make_global_planner("global_planner/GlobalPlanner", {"use_grid_path": True})
    path = grid_path.plan(grid, (1.02, 1.02, 0), (3.02, 1.02, 0))
    np.testing.assert_allclose(path[:-1, 1], 1.05)
    np.testing.assert_allclose(path[:-1, 0], np.arange(1.05, 3.06, 0.1))
    assert isinstance(grid_path, GlobalPlannerPlugin)
    pot = grid_path.potential
    assert pot is not None
    assert pot[10, 10] == 0.0
    assert pot[0, 0] == POT_HIGH


def _astar_potential(costs: npt.NDArray[np.uint8], **params: object) -> npt.NDArray[np.float32]:
    planner = make_global_planner(
        "global_planner/GlobalPlanner", {"use_dijkstra": False, "use_grid_path": True, **params}
    )
    assert isinstance(planner, GlobalPlannerPlugin)
    planner.plan(CostGrid(costs, RES), (1.05, 1.05, 0), (2.05, 2.05, 0))
    assert planner.potential is not None
    return planner.potential


def test_astar_uses_the_quadratic_potential_unless_told_not_to() -> None:
    costs = np.zeros((40, 40), dtype=np.uint8)
    quadratic = _astar_potential(costs)
    plain = _astar_potential(costs, use_quadratic=False)
    # the start is cell (10, 10); a step costs neutral_cost (50) on free cells
    assert plain[10, 11] == quadratic[10, 11] == 50.0
    assert plain[11, 11] == 100.0  # two steps: the plain sum is a Manhattan distance
    # the quadratic calculator interpolates between the two neighbours (navfn's update)
    assert quadratic[11, 11] == pytest.approx(50.0 + 50.0 * 0.7040, rel=1e-6)
    assert quadratic[20, 20] < 0.85 * plain[20, 20]


def test_astar_steps_wrap_in_eight_bits_as_in_ros() -> None:
    costs = np.zeros((40, 40), dtype=np.uint8)
    costs[10, 11] = 220  # 220 + neutral_cost 50 = 270, an unsigned char of 14
    costs[11, 10] = 100
    plain = _astar_potential(costs, use_quadratic=False)
    assert plain[10, 11] == 14.0
    assert plain[11, 10] == 150.0


def test_clear_endpoint_lets_a_goal_just_inside_an_obstacle_be_planned_to() -> None:
    costs = np.zeros((40, 40), dtype=np.uint8)
    costs[20:30, 20:30] = LETHAL
    grid = CostGrid(costs, RES)
    goal = (2.15, 2.25, 0.0)  # cell (21, 22): two cells inside the block's lower-left corner
    for params in ({}, {"use_grid_path": True}, {"use_quadratic": False}):
        path = make_global_planner("global_planner/GlobalPlanner", params).plan(
            grid, (1.0, 1.0, 0), goal
        )
        assert path[-1].tolist() == list(goal)
        assert math.hypot(path[-2, 0] - goal[0], path[-2, 1] - goal[1]) < 0.1
    # three cells deep is beyond clearEndpoint's reach
    with pytest.raises(NoPathError):
        make_global_planner("global_planner/GlobalPlanner", {}).plan(
            grid, (1.0, 1.0, 0), (2.35, 2.35, 0.0)
        )
    # old_navfn_behavior skips clearEndpoint; A* never expands a lethal goal cell
    for params in ({"old_navfn_behavior": True}, {"use_dijkstra": False}):
        with pytest.raises(NoPathError, match=r"no path from \(1\.00, 1\.00\)"):
            make_global_planner("global_planner/GlobalPlanner", params).plan(
                grid, (1.0, 1.0, 0), goal
            )


def _straight(mode: int, window: int = 1) -> npt.NDArray[np.float64]:
    grid = CostGrid(np.zeros((40, 40), dtype=np.uint8), RES)
    planner = make_global_planner(
        "global_planner/GlobalPlanner",
        {"use_grid_path": True, "orientation_mode": mode, "orientation_window_size": window},
    )
    return planner.plan(grid, (1.02, 1.02, 0.3), (1.02, 3.02, 1.0))


def test_orientation_modes() -> None:
    up = math.pi / 2
    none = _straight(0)
    assert (none[:-1, 2] == 0).all()
    assert none[-1, 2] == 1.0
    # the pose before the goal looks at the goal itself (off the cell centres here)
    np.testing.assert_allclose(_straight(1)[:-2, 2], up)
    np.testing.assert_allclose(_straight(4)[:-2, 2], -up)
    np.testing.assert_allclose(_straight(5)[:-2, 2], 0.0, atol=1e-12)
    np.testing.assert_allclose(_straight(6)[:-2, 2], math.pi)
    interpolated = _straight(2)
    assert interpolated[0, 2] == 0.3
    np.testing.assert_allclose(interpolated[-1, 2], 1.0)
    assert (np.diff(interpolated[:, 2]) > 0).all()
    then = _straight(3)
    assert then[0, 2] == 0.3
    assert (then[1:-3, 2] > 0.3).all()
    assert np.isfinite(_straight(1, window=5)[:, 2]).all()


def test_plugin_names_and_parameter_errors() -> None:
    with pytest.raises(UnknownPluginError, match=r"'dstar/DStar' \(supported: navfn/NavfnROS"):
        make_global_planner("dstar/DStar", {})
    with pytest.raises(ValueError, match=r"'orientation_mode' must be 0 to 6, not 9"):
        make_global_planner("global_planner/GlobalPlanner", {"orientation_mode": 9})
    with pytest.raises(ValueError, match=r"'allow_unknown' must be true or false"):
        make_global_planner("navfn/NavfnROS", {"allow_unknown": "yes"})
    with pytest.raises(ValueError, match=r"'lethal_cost' \(300\)"):
        make_global_planner("global_planner/GlobalPlanner", {"lethal_cost": 300})
