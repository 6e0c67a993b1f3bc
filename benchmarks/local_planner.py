"""The local planners' control cycle against the controller period it must fit in.

The reference is the period itself: move_base calls the local planner every
1/controller_frequency seconds (the course uses 3-10 Hz), and a cycle must end well inside
it. Each configuration drives a kinematic robot (the course's 0.2 m-radius mbot outline)
along a plan through a 10 m x 10 m local costmap of 200 x 200 cells with walls and pillars,
inflated as costmap_2d does, and times every compute() call (both distance-map wavefronts,
all rollouts and their scoring).

    python benchmarks/local_planner.py [--cycles 60]
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import statistics
import time
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy.ndimage import distance_transform_edt

from belvedere.nav.costmap import INSCRIBED, LETHAL, CostGrid
from belvedere.nav.local import make_local_planner

Floats = npt.NDArray[np.float64]
RES = 0.05
RADIUS = 0.2


def world() -> CostGrid:
    """A cloister-like 10 m square: an outer wall, an inner courtyard wall with four
    openings, and pillars along the walk; inflated to 0.5 m."""
    n = 200
    lethal = np.zeros((n, n), dtype=bool)
    lethal[[0, -1], :] = True
    lethal[:, [0, -1]] = True
    inner = slice(60, 140)
    lethal[60, inner] = lethal[139, inner] = True
    lethal[inner, 60] = lethal[inner, 139] = True
    for gap in (slice(95, 105),):
        lethal[60, gap] = lethal[139, gap] = False
        lethal[gap, 60] = lethal[gap, 139] = False
    for k in range(30, 171, 20):
        lethal[28:32, k : k + 3] = True
        lethal[k : k + 3, 168:172] = True
    dist = distance_transform_edt(~lethal) * RES
    costs = np.zeros((n, n), dtype=np.uint8)
    ring = (dist > RADIUS) & (dist <= 0.5)
    costs[ring] = (252 * np.exp(-5.0 * (dist[ring] - RADIUS))).astype(np.uint8)
    costs[dist <= RADIUS] = INSCRIBED
    costs[lethal] = LETHAL
    return CostGrid(costs, RES, 0.0, 0.0)


def plan() -> Floats:
    """Along the southern walk and up the eastern one, round the pillars."""
    corners = [(1.2, 0.75), (8.05, 0.75), (8.05, 8.0)]
    points = []
    for (x0, y0), (x1, y1) in itertools.pairwise(corners):
        n = math.ceil(math.hypot(x1 - x0, y1 - y0) / RES)
        t = np.linspace(0, 1, n, endpoint=False)
        yaw = math.atan2(y1 - y0, x1 - x0)
        points.append(np.column_stack([x0 + t * (x1 - x0), y0 + t * (y1 - y0), np.full(n, yaw)]))
    points.append(np.array([[corners[-1][0], corners[-1][1], math.pi / 2]]))
    return np.vstack(points)


def circle_footprint() -> Floats:
    # costmap_2d's footprint for robot_radius: 16 points on the circle
    a = np.linspace(0, 2 * math.pi, 16, endpoint=False)
    return np.column_stack([RADIUS * np.cos(a), RADIUS * np.sin(a)])


CONFIGS: list[tuple[str, str, dict[str, Any]]] = [
    (
        "TrajectoryPlannerROS, the course's mbot_navigation values",
        "base_local_planner/TrajectoryPlannerROS",
        {
            "controller_frequency": 3.0,
            "max_vel_x": 0.5,
            "min_vel_x": 0.1,
            "min_in_place_vel_theta": 0.5,
            "acc_lim_x": 1.5,
            "acc_lim_theta": 1.2,
            "holonomic_robot": False,
            "pdist_scale": 0.9,
            "gdist_scale": 0.6,
            "meter_scoring": True,
            "occdist_scale": 0.1,
            "vx_samples": 8,
            "vtheta_samples": 20,
        },
    ),
    (
        "TrajectoryPlannerROS, defaults (holonomic)",
        "base_local_planner/TrajectoryPlannerROS",
        {"controller_frequency": 10.0},
    ),
    (
        "DWAPlannerROS, defaults for a differential robot",
        "dwa_local_planner/DWAPlannerROS",
        {"controller_frequency": 10.0, "max_vel_y": 0.0, "min_vel_y": 0.0},
    ),
    (
        "DWAPlannerROS, defaults (holonomic, 3 x 10 x 20 samples)",
        "dwa_local_planner/DWAPlannerROS",
        {"controller_frequency": 10.0},
    ),
    (
        "DWAPlannerROS, 10 x 10 x 20 samples at 5 Hz",
        "dwa_local_planner/DWAPlannerROS",
        {"controller_frequency": 5.0, "vx_samples": 10},
    ),
]


def run(plugin: str, params: dict[str, Any], cycles: int) -> tuple[list[float], list[float], float]:
    grid = world()
    footprint = circle_footprint()
    planner = make_local_planner(plugin, params)
    period = planner.params.sim_period
    planner.set_plan(plan())
    pose = np.array([1.2, 0.75, 0.0])
    velocity = np.zeros(3)
    times: list[float] = []
    cpu: list[float] = []
    for _ in range(cycles):
        if planner.goal_reached(pose, velocity):
            break
        started, cpu_started = time.perf_counter(), time.process_time()
        command = planner.compute(grid, pose, velocity, footprint)
        times.append(time.perf_counter() - started)
        cpu.append(time.process_time() - cpu_started)
        velocity = np.array([command.vx, command.vy, command.vth])
        c, s = math.cos(pose[2]), math.sin(pose[2])
        pose = pose + period * np.array(
            [velocity[0] * c - velocity[1] * s, velocity[0] * s + velocity[1] * c, velocity[2]]
        )
    return times, cpu, period


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cycles", type=int, default=60)
    args = parser.parse_args()
    print(f"local costmap 200 x 200 cells at {RES} m; {args.cycles} cycles each")
    for title, plugin, params in CONFIGS:
        times, cpu, period = run(plugin, params, args.cycles)
        median = statistics.median(times)
        worst = max(times)
        cpu_median = statistics.median(cpu)
        print(
            f"{title}:\n  cycle median {1e3 * median:6.1f} ms (CPU {1e3 * cpu_median:5.1f} ms)"
            f", max {1e3 * worst:6.1f} ms; period {1e3 * period:.0f} ms -> "
            f"{100 * median / period:4.1f}% of the period (max {100 * worst / period:.1f}%)"
        )
    print(f"load average while measuring: {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")


if __name__ == "__main__":
    main()
