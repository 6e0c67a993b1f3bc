"""costmap_2d over numpy: inflation against its formula, the static layer's values, marking
and ray-traced clearing, both parameter styles from the course's YAML, the rolling window,
footprints, and the errors bad parameters give."""

from __future__ import annotations

import copy
import math
from typing import Any

import numpy as np
import pytest
import yaml

from belvedere.nav.costmap import (
    FREE,
    INSCRIBED,
    LETHAL,
    NO_INFORMATION,
    CostmapParams,
    InflationLayer,
    LayeredCostmap,
    Observation,
    ObstacleParams,
    StaticParams,
    circle_footprint,
    convex_fill,
    inflation_cost,
    radii,
    raytrace,
)
from belvedere.nav.costmap._layers import StaticLayer

# The course's costmap_common_params.yaml (mbot_navigation), with its global and local files.
COMMON = """
obstacle_range: 2.5
raytrace_range: 3.0
robot_radius: 0.175
inflation_radius: 0.5
max_obstacle_height: 0.6
min_obstacle_height: 0.0
observation_sources: scan
scan: {data_type: LaserScan, topic: /scan, marking: true, clearing: true, expected_update_rate: 0}
"""
GLOBAL = """
global_frame: map
robot_base_frame: base_footprint
update_frequency: 1.0
publish_frequency: 1.0
static_map: true
rolling_window: false
resolution: 0.05
transform_tolerance: 1.0
map_type: costmap
"""
LOCAL = """
global_frame: odom
robot_base_frame: base_footprint
update_frequency: 3.0
publish_frequency: 1.0
static_map: false
rolling_window: true
width: 3.0
height: 3.0
resolution: 0.05
transform_tolerance: 1.0
"""
LAYERED = """
global_frame: map
robot_base_frame: base_footprint
resolution: 0.05
robot_radius: 0.175
plugins:
  - {name: static_layer, type: "costmap_2d::StaticLayer"}
  - {name: obstacle_layer, type: "costmap_2d::ObstacleLayer"}
  - {name: inflation_layer, type: "costmap_2d::InflationLayer"}
obstacle_layer:
  obstacle_range: 2.5
  raytrace_range: 3.0
  max_obstacle_height: 0.6
  observation_sources: scan
  scan: {data_type: LaserScan, topic: /scan, marking: true, clearing: true}
inflation_layer: {inflation_radius: 0.5, cost_scaling_factor: 10.0}
"""


def _params(*texts: str, **extra: Any) -> dict[str, Any]:
    merged: dict[str, Any] = {}
    for text in texts:
        merged.update(yaml.safe_load(text))
    merged.update(extra)
    return merged


def _room(size: int = 80) -> np.ndarray[Any, np.dtype[np.int8]]:
    """A map: walls round the edge, a pillar, an unknown corner (OccupancyGrid values)."""
    data = np.zeros((size, size), dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 100
    data[30:34, 50:54] = 100
    data[70:79, 70:79] = -1
    return data


def _scan_ring(x: float, y: float, radius: float, z: float = 0.2) -> Observation:
    angles = np.linspace(-math.pi, math.pi, 720, endpoint=False)
    points = np.column_stack(
        [x + radius * np.cos(angles), y + radius * np.sin(angles), np.full(720, z)]
    )
    return Observation(np.array([x, y, z]), points, 0)


def test_inflation_matches_costmap_2ds_formula_cell_by_cell() -> None:
    params = CostmapParams.from_mapping(
        _params(
            "{plugins: [{name: inflation, type: 'costmap_2d::InflationLayer'}]}",
            robot_radius=0.2,
            footprint_padding=0.0,
            width=3.0,
            height=3.0,
            inflation={"inflation_radius": 0.62, "cost_scaling_factor": 3.0},
        )
    )
    costmap = LayeredCostmap(params)
    costmap.update((1.5, 1.5, 0.0), 0)
    costmap.master.costs[30, 30] = LETHAL
    layer = costmap.layers[0][1]
    assert isinstance(layer, InflationLayer)
    layer.update(costmap.master, costmap.inscribed_radius)
    inscribed = costmap.inscribed_radius
    assert inscribed == pytest.approx(0.2 * math.cos(math.pi / 16))
    rows, cols = np.mgrid[0:60, 0:60]
    cells = np.hypot(rows - 30, cols - 30)
    expected = np.zeros((60, 60), dtype=np.int64)
    for (j, i), d in np.ndenumerate(cells):
        if d > math.ceil(0.62 / 0.05):
            continue
        if d == 0:
            expected[j, i] = 254
        elif d * 0.05 <= inscribed:
            expected[j, i] = 253
        else:
            expected[j, i] = int(252 * math.exp(-3.0 * (d * 0.05 - inscribed)))
    assert np.array_equal(costmap.master.costs, expected)
    # the radius is whole cells rounded up: 0.62 m is 13 cells, 13 cells away still costs
    assert costmap.master.costs[30, 43] == int(252 * math.exp(-3.0 * (0.65 - inscribed))) > 0
    assert costmap.master.costs[30, 44] == FREE


def test_inflation_cost_function_edges() -> None:
    d = np.array([0.0, 1.0, 4.0, 5.0, 10.0])
    costs = inflation_cost(d, 0.05, 0.2, 10.0)
    assert costs.tolist() == [254, 253, 253, int(252 * math.exp(-0.5)), int(252 * math.exp(-3.0))]


def test_inflation_leaves_unknown_cells_unknown_unless_inscribed() -> None:
    params = CostmapParams.from_mapping(
        _params(COMMON, GLOBAL, track_unknown_space=True, robot_radius=0.1)
    )
    costmap = LayeredCostmap(params)
    data = np.full((40, 40), -1, dtype=np.int8)
    data[20, 20] = 100
    costmap.set_map(data, 0.05, (0.0, 0.0), "map")
    costmap.update((0.3, 0.3, 0.0), 0)
    grid = costmap.master.costs
    assert grid[20, 20] == LETHAL
    assert grid[20, 21] == INSCRIBED  # inscribed replaces unknown
    assert grid[20, 25] == NO_INFORMATION  # a lower cost does not


def test_static_layer_interprets_map_values() -> None:
    values = np.array([[0, 50, 99, 100, -1]], dtype=np.int8)
    trinary = StaticLayer(StaticParams("s"))
    assert trinary.interpret(values).tolist() == [[0, 0, 0, 254, 255]]
    scaled = StaticLayer(StaticParams("s", trinary_costmap=False, track_unknown_space=False))
    assert scaled.interpret(values).tolist() == [[0, 127, 251, 254, 0]]
    threshold = StaticLayer(StaticParams("s", lethal_cost_threshold=50))
    assert threshold.interpret(values).tolist() == [[0, 254, 254, 254, 255]]


def test_the_grid_takes_the_static_maps_size_and_origin() -> None:
    costmap = LayeredCostmap(CostmapParams.from_mapping(_params(COMMON, GLOBAL)))
    assert costmap.master.costs.shape == (200, 200)  # width/height 10 m by default
    costmap.set_map(_room(), 0.05, (-1.0, -2.0), "map")
    costmap.update((1.0, 0.0, 0.0), 0)
    grid = costmap.master
    assert (grid.width, grid.height, grid.origin_x, grid.origin_y) == (80, 80, -1.0, -2.0)
    assert grid.costs[31, 51] == LETHAL
    # the costmap's track_unknown_space (false) is copied into the static layer
    assert (grid.costs != NO_INFORMATION).all()
    tracking = LayeredCostmap(
        CostmapParams.from_mapping(_params(COMMON, GLOBAL, track_unknown_space=True))
    )
    tracking.set_map(_room(), 0.05, (-1.0, -2.0), "map")
    tracking.update((1.0, 0.0, 0.0), 0)
    assert tracking.master.costs[74, 74] == NO_INFORMATION


def test_marking_keeps_within_obstacle_range_and_height() -> None:
    costmap = LayeredCostmap(CostmapParams.from_mapping(_params(COMMON, GLOBAL)))
    costmap.set_map(np.zeros((100, 100), dtype=np.int8), 0.05, (0.0, 0.0), "map")
    origin = np.array([2.5, 2.5, 0.2])
    points = np.array(
        [
            [3.5, 2.5, 0.2],  # 1 m: marked
            [2.5, 4.9, 0.2],  # 2.4 m: marked
            [0.0, 2.5, 0.2],  # 2.5 m: obstacle_range is exclusive
            [2.5, 1.5, 0.7],  # above max_obstacle_height 0.6
            [1.5, 2.5, 2.1],  # above the source's max_obstacle_height (2.0): filtered
        ]
    )
    costmap.add_observation("scan", Observation(origin, points, 0), 0)
    costmap.update((2.5, 2.5, 0.0), 0)
    layer = costmap.obstacle_layers[0]
    assert layer.grid is not None
    marked = set(map(tuple, np.argwhere(layer.grid.costs == LETHAL).tolist()))
    assert marked == {(50, 70), (98, 50)}


def test_ray_tracing_clears_what_a_later_scan_sees_through() -> None:
    costmap = LayeredCostmap(CostmapParams.from_mapping(_params(COMMON, GLOBAL)))
    costmap.set_map(np.zeros((200, 200), dtype=np.int8), 0.05, (0.0, 0.0), "map")
    costmap.add_observation("scan", _scan_ring(5.0, 5.0, 1.0), 0)
    costmap.update((5.0, 5.0, 0.0), 0)
    assert costmap.master.costs[100, 120] == LETHAL
    # the obstacle moved away: the new ring is beyond it, every ray passes through the old one
    costmap.add_observation("scan", _scan_ring(5.0, 5.0, 2.0), 1)
    costmap.update((5.0, 5.0, 0.0), 1)
    layer = costmap.obstacle_layers[0]
    assert layer.grid is not None
    ring = np.hypot(*(np.mgrid[0:200, 0:200] - 99.5)) * 0.05
    old = (ring > 0.97) & (ring < 1.03)
    assert (layer.grid.costs[old] == FREE).all()
    assert costmap.master.costs[100, 140] == LETHAL
    # raytrace_range (3 m) bounds clearing: a ring at 3.5 m clears 2.9 m out, not 3.2 m
    layer.grid.costs[100, 100 + 58] = LETHAL
    layer.grid.costs[100, 100 + 64] = LETHAL
    costmap.add_observation("scan", _scan_ring(5.0, 5.0, 3.5), 2)
    costmap.update((5.0, 5.0, 0.0), 2)
    assert layer.grid.costs[100, 100 + 58] == FREE
    assert layer.grid.costs[100, 100 + 64] == LETHAL
    # and a point beyond obstacle_range (2.5 m) is not marked
    assert layer.grid.costs[100, 100 + 70] == FREE


def _bresenham(x0: int, y0: int, x1: int, y1: int, max_length: float) -> list[tuple[int, int]]:
    """costmap_2d's raytraceLine, one cell at a time (the reference for the vectorised one)."""
    dx, dy = x1 - x0, y1 - y0
    adx, ady = abs(dx), abs(dy)
    dist = math.hypot(dx, dy)
    scale = 1.0 if dist == 0 else min(1.0, max_length / dist)
    sx, sy = (1 if dx > 0 else -1), (1 if dy > 0 else -1)
    x, y = x0, y0
    cells = []
    if adx >= ady:
        error, end = adx // 2, int(scale * adx)
        for _ in range(end):
            cells.append((x, y))
            x += sx
            error += ady
            if error >= adx:
                y += sy
                error -= adx
    else:
        error, end = ady // 2, int(scale * ady)
        for _ in range(end):
            cells.append((x, y))
            y += sy
            error += adx
            if error >= ady:
                x += sx
                error -= ady
    cells.append((x, y))
    return cells


def test_vectorised_ray_tracing_walks_bresenhams_cells() -> None:
    rng = np.random.default_rng(3)
    ends = rng.integers(-40, 40, size=(300, 2))
    cols, rows = raytrace(0, 0, ends, 25.0)
    got = list(zip(cols.tolist(), rows.tolist(), strict=True))
    expected = [cell for end in ends for cell in _bresenham(0, 0, int(end[0]), int(end[1]), 25.0)]
    assert got == expected


def test_convex_fill_is_the_outline_and_each_columns_span() -> None:
    rng = np.random.default_rng(5)
    for _ in range(20):
        angles = np.sort(rng.uniform(0, 2 * math.pi, 6))
        radius = rng.uniform(3, 12)
        vertices = np.column_stack(
            [20 + radius * np.cos(angles), 20 + radius * np.sin(angles)]
        ).astype(np.int64)
        corners = [(int(x), int(y)) for x, y in vertices]
        outline = {
            cell
            for (x0, y0), (x1, y1) in zip(corners, corners[1:] + corners[:1], strict=True)
            for cell in _bresenham(x0, y0, x1, y1, math.inf)
        }
        expected = set()
        for col in {c for c, _ in outline}:
            span = [r for c, r in outline if c == col]
            expected |= {(col, r) for r in range(min(span), max(span) + 1)}
        cols, rows = convex_fill(vertices, 40, 40)
        assert set(zip(cols.tolist(), rows.tolist(), strict=True)) == expected


def test_both_parameter_styles_give_the_same_grid() -> None:
    old = LayeredCostmap(CostmapParams.from_mapping(_params(COMMON, GLOBAL)))
    new = LayeredCostmap(CostmapParams.from_mapping(_params(LAYERED)))
    assert old.params.pre_hydro
    assert not new.params.pre_hydro
    assert [type(layer).__name__ for _, layer in old.layers] == [
        type(layer).__name__ for _, layer in new.layers
    ]
    for costmap in (old, new):
        costmap.set_map(_room(), 0.05, (0.0, 0.0), "map")
        costmap.add_observation("scan", _scan_ring(1.5, 2.0, 0.8), 0)
        costmap.update((1.5, 2.0, 0.0), 0)
    assert (old.master.costs == LETHAL).sum() > 100
    assert np.array_equal(old.master.costs, new.master.costs)


def test_the_footprint_is_cleared_and_the_rolling_window_follows_the_robot() -> None:
    costmap = LayeredCostmap(CostmapParams.from_mapping(_params(COMMON, LOCAL)))
    assert costmap.master.costs.shape == (60, 60)
    costmap.update((10.0, 5.0, 0.0), 0)
    assert (costmap.master.origin_x, costmap.master.origin_y) == pytest.approx((8.5, 3.5))
    costmap.add_observation("scan", _scan_ring(10.0, 5.0, 1.0), 0)
    costmap.update((10.0, 5.0, 0.0), 0)
    assert costmap.master.costs[30, 50] == LETHAL  # 1 m ahead of the robot
    # 0.52 m on: the window moves by whole cells (10 of 0.05 m) and keeps what it saw
    costmap.update((10.52, 5.0, 0.0), 0)
    assert costmap.master.origin_x == pytest.approx(9.0)
    assert costmap.master.costs[30, 40] == LETHAL
    # an obstacle under the robot is cleared with its footprint
    layer = costmap.obstacle_layers[0]
    assert layer.grid is not None
    layer.grid.costs[30, 30] = LETHAL
    costmap.update((10.52, 5.0, 0.0), 0)
    assert layer.grid.costs[30, 30] == FREE


LAYERS_TWO_OBSTACLES = """
global_frame: map
robot_base_frame: base_footprint
resolution: 0.05
robot_radius: 0.175
plugins:
  - {name: static_layer, type: "costmap_2d::StaticLayer"}
  - {name: obstacles, type: "costmap_2d::ObstacleLayer"}
  - {name: sonar, type: "costmap_2d::ObstacleLayer"}
  - {name: inflation_layer, type: "costmap_2d::InflationLayer"}
obstacles:
  observation_sources: scan
  scan: {data_type: LaserScan, topic: /scan, marking: true, clearing: false}
sonar:
  observation_sources: range
  range: {data_type: PointCloud2, topic: /range, marking: true, clearing: false}
inflation_layer: {inflation_radius: 0.1}
"""


def _seen(costmap: LayeredCostmap) -> None:
    """Obstacles 0.5 m and 2 m from (2.5, 2.5) in both obstacle layers, then no more readings."""
    near, far = _scan_ring(2.5, 2.5, 0.5), _scan_ring(2.5, 2.5, 2.0)
    both = Observation(near.origin, np.concatenate([near.points, far.points]), 0)
    costmap.add_observation("scan", both, 0)
    costmap.add_observation("range", both, 0)
    costmap.update((2.5, 2.5, 0.0), 0)
    for layer in costmap.obstacle_layers:
        for buffer in layer.buffers.values():
            buffer.observations.clear()


def test_clearing_resets_only_the_named_layers_outside_the_window() -> None:
    costmap = LayeredCostmap(CostmapParams.from_mapping(yaml.safe_load(LAYERS_TWO_OBSTACLES)))
    costmap.set_map(np.zeros((100, 100), dtype=np.int8), 0.05, (0.0, 0.0), "map")
    _seen(costmap)
    obstacles, sonar = (layer.grid for layer in costmap.obstacle_layers)
    assert obstacles is not None
    assert sonar is not None
    assert obstacles.costs[50, 90] == sonar.costs[50, 90] == LETHAL
    # ClearCostmapRecovery's default layer_names: ["obstacles"]; missing names are reported
    missing, not_clearable = costmap.clear_area(2.5, 2.5, 2.0, ["obstacles", "voxels"])
    assert (missing, not_clearable) == (["voxels"], [])
    assert obstacles.costs[50, 90] == NO_INFORMATION  # 2 m away: outside the 2 m square
    assert obstacles.costs[50, 60] == LETHAL  # 0.5 m: inside
    assert sonar.costs[50, 90] == LETHAL  # not named: kept
    costmap.update((2.5, 2.5, 0.0), 0)
    assert costmap.master.costs[50, 90] == LETHAL  # the sonar still sees it
    costmap.clear_area(2.5, 2.5, 2.0, ["sonar", "layers/obstacles"])  # names after the last /
    costmap.update((2.5, 2.5, 0.0), 0)
    assert costmap.master.costs[50, 90] == FREE  # no layer has an opinion: the map's free
    assert costmap.master.costs[50, 60] == LETHAL
    # the square's edge cells are cleared: the window keeps the cells strictly inside it
    assert sonar.costs[50, 30] == NO_INFORMATION
    assert sonar.costs[50, 31] == FREE
    # inflation has no cells of its own to clear
    assert costmap.clear_area(2.5, 2.5, 2.0, ["inflation_layer"]) == ([], ["inflation_layer"])


def test_clearing_inside_the_window_and_the_static_layer() -> None:
    costmap = LayeredCostmap(CostmapParams.from_mapping(yaml.safe_load(LAYERS_TWO_OBSTACLES)))
    room = np.zeros((100, 100), dtype=np.int8)
    room[:, 95:] = 100
    costmap.set_map(room, 0.05, (0.0, 0.0), "map")
    _seen(costmap)
    costmap.clear_area(2.5, 2.5, 2.0, ["obstacles", "sonar"], invert=True)
    costmap.update((2.5, 2.5, 0.0), 0)
    assert costmap.master.costs[50, 60] == FREE  # inside: cleared
    assert costmap.master.costs[50, 90] == LETHAL  # outside: kept
    assert costmap.master.costs[50, 97] == LETHAL  # the map's wall
    costmap.clear_area(2.5, 2.5, 2.0, ["static_layer"])
    costmap.update((2.5, 2.5, 0.0), 0)
    assert costmap.static_layers[0].map is not None
    assert costmap.static_layers[0].map.costs[50, 97] == NO_INFORMATION
    # gone until the next map; the obstacle layers' free cells fill the unknown master cell
    assert costmap.master.costs[50, 97] == FREE


@pytest.mark.parametrize("config", ["global", "local"])
def test_an_update_rewrites_only_what_changed_and_equals_a_full_rebuild(config: str) -> None:
    if config == "global":
        values = _params(COMMON, GLOBAL)
    else:  # the local window, bigger than the scans so it need not move with the robot
        values = _params(COMMON, LOCAL, width=6.0, height=6.0)
    costmap = LayeredCostmap(CostmapParams.from_mapping(values))
    costmap.set_map(_room(), 0.05, (0.0, 0.0), "map")
    rng = np.random.default_rng(7)
    partial = 0
    for step in range(12):
        x, y = 1.5 + 0.004 * step, 2.0 + 0.003 * step  # under a cell: the window stays
        scan = _scan_ring(x, y, 0.6 + 0.1 * (step % 4))
        kept = rng.random(len(scan.points)) < 0.7  # a different subset of beams each time
        costmap.add_observation("scan", Observation(scan.origin, scan.points[kept], 0), 0)
        reference = copy.deepcopy(costmap)
        reference.rebuild_all()
        costmap.update((x, y, 0.0), 0)
        reference.update((x, y, 0.0), 0)
        assert np.array_equal(costmap.master.costs, reference.master.costs), step
        assert costmap.last_window is not None
        rows, cols = costmap.last_window
        partial += (rows.stop - rows.start) * (cols.stop - cols.start) < costmap.master.costs.size
        for layer in costmap.obstacle_layers:
            for buffer in layer.buffers.values():
                buffer.observations.clear()
    assert (costmap.master.costs == LETHAL).sum() > 50
    assert partial >= 10  # all but the first update (and a moved window) were partial


def test_footprints_and_their_radii() -> None:
    square = np.array([[0.2, 0.1], [0.2, -0.1], [-0.2, -0.1], [-0.2, 0.1]])
    assert radii(square) == pytest.approx((0.1, math.hypot(0.2, 0.1)))
    params = CostmapParams.from_mapping(
        {"footprint": "[[0.2, 0.1], [0.2, -0.1], [-0.2, -0.1], [-0.2, 0.1]]"}
    )
    np.testing.assert_allclose(
        params.footprint, [[0.21, 0.11], [0.21, -0.11], [-0.21, -0.11], [-0.21, 0.11]]
    )
    circle = circle_footprint(0.3)
    assert len(circle) == 16
    assert radii(circle) == pytest.approx((0.3 * math.cos(math.pi / 16), 0.3))


@pytest.mark.parametrize(
    ("values", "pattern"),
    [
        ({"map_type": "octomap"}, r"'map_type' must be 'costmap' or 'voxel', not 'octomap'"),
        ({"footprint": [[0.1, 0.1], [0.2, 0.2]]}, r"'footprint' must be a polygon of at least 3"),
        ({"footprint": "[[0.1, oops]]"}, r"'footprint' must be a polygon"),
        ({"observation_sources": "scan"}, r"'scan' must be a namespace of parameters, not missing"),
        (
            {"observation_sources": "scan", "scan": {"data_type": "Sonar"}},
            r"'scan/data_type' must be one of LaserScan, PointCloud, PointCloud2, not 'Sonar'",
        ),
        (
            {"plugins": [{"name": "x", "type": "costmap_2d::RangeSensorLayer"}]},
            r"unknown layer type 'costmap_2d::RangeSensorLayer' \(supported: costmap_2d::Static",
        ),
        ({"resolution": 0}, r"'resolution' must be positive"),
        ({"inflation_radius": "wide"}, r"'inflation_radius' must be a number"),
    ],
)
def test_bad_parameters_name_the_parameter(values: dict[str, Any], pattern: str) -> None:
    with pytest.raises(ValueError, match=pattern):
        CostmapParams.from_mapping(values)


def test_voxel_map_type_is_the_obstacle_layer_in_2d() -> None:
    params = CostmapParams.from_mapping(_params(COMMON, GLOBAL, map_type="voxel"))
    obstacle = params.layers[1]
    assert isinstance(obstacle, ObstacleParams)
    assert obstacle.voxel
    assert obstacle.sources[0].obstacle_range == 2.5
