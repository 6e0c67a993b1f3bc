"""Global planning across a 400 x 400 cloister-like costmap, against the planner's period.

Builds the map (20 x 20 m at 0.05 m: outer walls, a cloister of arcades round a courtyard
with pillars, side rooms with doors), makes the global costmap from it with the course's
parameters (static, obstacle and inflation layers; one laser scan marked), times the costmap
update, then plans corner to corner and into the courtyard with each planner configuration,
and prints each planning time with its ratio to move_base's planning period
(``1 / planner_frequency``; the course plans at 1 Hz, ``--planner-frequency`` to change).

    python benchmarks/global_planner.py [--repeat 5] [--planner-frequency 1.0]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.nav.costmap import CostmapParams, LayeredCostmap, Observation
from belvedere.nav.planners import make_global_planner

SIZE = 400
RESOLUTION = 0.05
COSTMAP: dict[str, Any] = {
    "obstacle_range": 2.5,
    "raytrace_range": 3.0,
    "robot_radius": 0.175,
    "inflation_radius": 0.5,
    "cost_scaling_factor": 10.0,
    "max_obstacle_height": 0.6,
    "observation_sources": "scan",
    "scan": {"data_type": "LaserScan", "topic": "/scan", "marking": True, "clearing": True},
    "global_frame": "map",
    "robot_base_frame": "base_footprint",
    "static_map": True,
    "map_type": "costmap",
}
PLANNERS: list[tuple[str, dict[str, Any]]] = [
    ("navfn/NavfnROS", {}),
    ("global_planner/GlobalPlanner", {}),
    ("global_planner/GlobalPlanner", {"use_quadratic": False}),
    ("global_planner/GlobalPlanner", {"use_dijkstra": False}),
    ("global_planner/GlobalPlanner", {"use_grid_path": True, "orientation_mode": 1}),
]
TRIPS = [((1.0, 1.0, 0.0), (19.0, 19.0, 0.0)), ((1.0, 19.0, 0.0), (10.0, 11.0, 1.57))]


def cloister() -> npt.NDArray[np.int8]:
    """OccupancyGrid values of the test world (100 walls, 0 free)."""
    occ = np.zeros((SIZE, SIZE), dtype=np.int8)
    occ[:4, :] = occ[-4:, :] = occ[:, :4] = occ[:, -4:] = 100
    occ[100:300, 100:300] = 100  # the cloister's inner wall ...
    occ[108:292, 108:292] = 0  # ... round the courtyard
    occ[190:210, 100:108] = 0  # doors into it
    occ[100:108, 190:210] = 0
    for j in range(130, 280, 30):  # pillars in the courtyard
        for i in range(130, 280, 30):
            occ[j : j + 4, i : i + 4] = 100
    occ[200:204, 4:70] = 100  # side rooms with doors
    occ[4:70, 200:204] = 100
    occ[200:204, 30:42] = 0
    occ[30:42, 200:204] = 0
    occ[330:334, 300:396] = 100
    return occ


def _median_ms(run: Any, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1000.0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--planner-frequency", type=float, default=1.0)
    args = parser.parse_args()
    period_ms = 1000.0 / args.planner_frequency

    costmap = LayeredCostmap(CostmapParams.from_mapping(COSTMAP))
    costmap.set_map(cloister(), RESOLUTION, (0.0, 0.0), "map")
    angles = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    ring = np.column_stack([5 + 2 * np.cos(angles), 5 + 2 * np.sin(angles), np.full(360, 0.2)])
    costmap.add_observation("scan", Observation(np.array([5.0, 5.0, 0.2]), ring, 0), 0)
    update_ms = _median_ms(lambda: costmap.update((5.0, 5.0, 0.0), 0), args.repeat)
    grid = costmap.master
    print(f"costmap {grid.width} x {grid.height}: update {update_ms:.1f} ms")
    print(f"planner period {period_ms:.0f} ms (planner_frequency {args.planner_frequency} Hz)")
    for plugin, params in PLANNERS:
        planner = make_global_planner(plugin, params)
        for start, goal in TRIPS:
            path = planner.plan(grid, start, goal)
            length = float(np.hypot(*np.diff(path[:, :2], axis=0).T).sum())
            ms = _median_ms(lambda p=planner, s=start, g=goal: p.plan(grid, s, g), args.repeat)
            label = f"{plugin} {params or ''}".strip()
            print(
                f"{label:70s} {start[:2]} -> {goal[:2]}: {ms:7.1f} ms "
                f"(ratio {ms / period_ms:.3f} of the period), path {length:.2f} m"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
