"""Hand-made cost grids and a kinematic robot for the local planner tests.

The grids are inflated as costmap_2d's inflation layer does it (lethal walls, inscribed
within the robot's inscribed radius, then exponentially decaying), and the robot integrates
each commanded twist exactly over the controller period in simulated time.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt
from scipy.ndimage import distance_transform_edt

from belvedere.nav.costmap import INSCRIBED, LETHAL, CostGrid
from belvedere.nav.local import Command, LocalPlanner

Floats = npt.NDArray[np.float64]

RESOLUTION = 0.05
SQUARE = np.array([[0.15, 0.15], [0.15, -0.15], [-0.15, -0.15], [-0.15, 0.15]])
"""A 30 cm square robot: inscribed radius 0.15 m, circumscribed 0.21 m."""
INSCRIBED_RADIUS = 0.15


def inflate(lethal: npt.NDArray[np.bool_], *, inflation_radius: float = 0.45) -> CostGrid:
    """costmap_2d's inflation of a lethal mask at :data:`RESOLUTION`."""
    dist = distance_transform_edt(~lethal) * RESOLUTION
    costs = np.zeros(lethal.shape, dtype=np.uint8)
    decay = 252 * np.exp(-10.0 * (dist - INSCRIBED_RADIUS))
    ring = (dist > INSCRIBED_RADIUS) & (dist <= inflation_radius)
    costs[ring] = decay[ring].astype(np.uint8)
    costs[dist <= INSCRIBED_RADIUS] = INSCRIBED
    costs[lethal] = LETHAL
    return CostGrid(costs, RESOLUTION, 0.0, 0.0)


def walled(width_m: float, height_m: float) -> npt.NDArray[np.bool_]:
    """A lethal mask of a room with a one-cell wall around it."""
    h, w = round(height_m / RESOLUTION), round(width_m / RESOLUTION)
    lethal = np.zeros((h, w), dtype=bool)
    lethal[0, :] = lethal[-1, :] = lethal[:, 0] = lethal[:, -1] = True
    return lethal


def corridor() -> CostGrid:
    """A 6 m x 2 m corridor along x (cells 0.05 m)."""
    return inflate(walled(6.0, 2.0))


def l_corridor() -> CostGrid:
    """An L-shaped corridor 1.2 m wide: east along y = 0.8 from x = 0.2 to 3.4, then north
    along x = 2.8 up to y = 4.8, in a 4 m x 5 m room."""
    lethal = np.ones((100, 80), dtype=bool)
    lethal[4:28, 4:68] = False  # y 0.2-1.4, x 0.2-3.4
    lethal[4:96, 44:68] = False  # x 2.2-3.4, y 0.2-4.8
    return inflate(lethal)


def polyline(*corners: tuple[float, float], goal_yaw: float, spacing: float = 0.025) -> Floats:
    """A global plan through the corners (as navfn gives one: a pose every cell or so), the
    poses facing along the path and the last facing ``goal_yaw``."""
    points: list[Floats] = []
    for (x0, y0), (x1, y1) in itertools.pairwise(corners):
        n = max(2, math.ceil(math.hypot(x1 - x0, y1 - y0) / spacing))
        t = np.linspace(0.0, 1.0, n, endpoint=False)
        yaw = math.atan2(y1 - y0, x1 - x0)
        points.append(np.column_stack([x0 + t * (x1 - x0), y0 + t * (y1 - y0), np.full(n, yaw)]))
    points.append(np.array([[corners[-1][0], corners[-1][1], goal_yaw]]))
    return np.vstack(points)


@dataclass
class Run:
    """What a drive recorded, one entry per control cycle."""

    poses: list[Floats] = field(default_factory=list)
    velocities: list[Floats] = field(default_factory=list)
    commands: list[Command] = field(default_factory=list)
    reached: bool = False

    @property
    def pose(self) -> Floats:
        return self.poses[-1]


def step(pose: Floats, twist: Floats, dt: float) -> Floats:
    """The pose after moving at the robot-frame twist for dt (an exact arc)."""
    x, y, yaw = pose
    vx, vy, vth = twist
    if abs(vth) < 1e-9:
        c, s = math.cos(yaw), math.sin(yaw)
        return np.array([x + (vx * c - vy * s) * dt, y + (vx * s + vy * c) * dt, yaw])
    new_yaw = yaw + vth * dt
    # integral of R(yaw(t)) @ (vx, vy) over the step
    sin_d = math.sin(new_yaw) - math.sin(yaw)
    cos_d = math.cos(new_yaw) - math.cos(yaw)
    dx = (vx * sin_d + vy * cos_d) / vth
    dy = (-vx * cos_d + vy * sin_d) / vth
    return np.array([x + dx, y + dy, math.remainder(new_yaw, math.tau)])


def drive(
    planner: LocalPlanner,
    grid: CostGrid,
    plan: Floats,
    start: tuple[float, float, float],
    *,
    footprint: Floats = SQUARE,
    cycles: int = 600,
) -> Run:
    """Drive a kinematic robot with the planner at its controller frequency until it
    reports the goal reached (as move_base asks before each cycle)."""
    period = planner.params.sim_period
    planner.set_plan(plan)
    pose = np.array(start, dtype=np.float64)
    velocity = np.zeros(3)
    run = Run()
    for _ in range(cycles):
        run.poses.append(pose)
        run.velocities.append(velocity)
        if planner.goal_reached(pose, velocity):
            run.reached = True
            return run
        command = planner.compute(grid, pose, velocity, footprint)
        run.commands.append(command)
        velocity = np.array([command.vx, command.vy, command.vth])
        pose = step(pose, velocity, period)
    return run


def cell_cost(grid: CostGrid, x: float, y: float) -> int:
    cell = grid.world_to_map(x, y)
    assert cell is not None, f"({x:.2f}, {y:.2f}) left the grid"
    return int(grid.costs[cell[1], cell[0]])
