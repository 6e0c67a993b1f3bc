"""What the local planners read off the cost grid: the plan's part in the grid, the path and
goal distance maps (base_local_planner's MapGrid) and the footprint's cost along rollouts.

Arrays are indexed ``[row, column]`` as :class:`~belvedere.nav.costmap.CostGrid` keeps them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import numpy.typing as npt
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import breadth_first_order

from belvedere.nav.costmap import INSCRIBED, LETHAL, NO_INFORMATION, CostGrid
from belvedere.nav.local._base import NoTrajectoryError

__all__ = [
    "DistanceMap",
    "FootprintModel",
    "clipped_cells",
    "filled_footprint_cells",
    "grid_cells",
    "plan_in_window",
    "prune_plan",
    "wavefront",
    "wavefronts",
]

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.intp]
Bools = npt.NDArray[np.bool_]


def plan_in_window(plan: Floats, grid: CostGrid, x: float, y: float) -> Floats:
    """The stretch of the plan the local grid can use: from the first pose within half the
    grid's larger side of the robot up to the next one beyond it (transformGlobalPlan)."""
    if len(plan) == 0:
        return plan
    reach = max(grid.width, grid.height) * grid.resolution / 2.0
    near = np.hypot(plan[:, 0] - x, plan[:, 1] - y) <= reach
    if not near.any():
        return plan[:0]
    start = int(np.argmax(near))
    beyond = np.flatnonzero(~near[start:])
    stop = start + int(beyond[0]) if len(beyond) else len(plan)
    return plan[start:stop]


def prune_plan(plan: Floats, x: float, y: float) -> int:
    """How many poses at the plan's start to drop: those before the first within 1 m of the
    robot (prunePlan; all of them when none is)."""
    near = np.flatnonzero(np.hypot(plan[:, 0] - x, plan[:, 1] - y) < 1.0)
    return int(near[0]) if len(near) else len(plan)


def follow_plan(
    plan: Floats, grid: CostGrid, x: float, y: float, *, prune: bool, planner: str
) -> tuple[Floats, Floats]:
    """The stretch of ``plan`` this cycle follows and the plan to keep (pruned behind the
    robot when ``prune``); :class:`NoTrajectoryError` in ``planner``'s name when there is
    none."""
    if len(plan) == 0:
        message = f"{planner}: no plan to follow"
        raise NoTrajectoryError(message)
    local = plan_in_window(plan, grid, x, y)
    if prune and len(local):
        drop = prune_plan(local, x, y)
        local = local[drop:]
        plan = plan[drop:]
    if len(local) == 0:
        message = f"{planner}: no pose of the plan lies in the local costmap"
        raise NoTrajectoryError(message)
    return local, plan


def _densify(points: Floats, step: float) -> Floats:
    """The polyline with points inserted so that neighbours are at most ``step`` apart
    (MapGrid's adjustPlanResolution)."""
    if len(points) < 2:
        return points
    seg = np.diff(points, axis=0)
    parts = np.maximum(1, np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / step)).astype(np.intp)
    owner = np.repeat(np.arange(len(seg)), parts)
    first = np.cumsum(parts) - parts
    frac = (np.arange(int(parts.sum())) - first[owner]) / parts[owner]
    dense = points[owner] + seg[owner] * frac[:, None]
    return np.vstack([dense, points[-1:]])


def grid_cells(grid: CostGrid, x: Floats, y: Floats) -> tuple[Ints, Ints, Bools]:
    """(column, row, inside) of world points (arrays of any one shape)."""
    i = np.floor((x - grid.origin_x) / grid.resolution).astype(np.intp)
    j = np.floor((y - grid.origin_y) / grid.resolution).astype(np.intp)
    inside = (i >= 0) & (i < grid.width) & (j >= 0) & (j < grid.height)
    return i, j, inside


def clipped_cells(grid: CostGrid, x: Floats, y: Floats) -> tuple[Ints, Ints, Bools]:
    """:func:`grid_cells` with points off the grid moved to its edge, so that every cell
    can be looked up (``inside`` says which were off)."""
    i, j, inside = grid_cells(grid, x, y)
    return np.clip(i, 0, grid.width - 1), np.clip(j, 0, grid.height - 1), inside


def _cells_of(grid: CostGrid, xy: Floats) -> tuple[Ints, Ints, Bools]:
    """(column, row, inside) of world points (any leading shape)."""
    return grid_cells(grid, xy[..., 0], xy[..., 1])


def plan_cells(grid: CostGrid, plan_xy: Floats) -> tuple[Ints, Ints]:
    """The (columns, rows) of the plan's first run of known cells inside the grid, at the
    grid's resolution (setTargetCells stops where the plan leaves the grid)."""
    dense = _densify(plan_xy, grid.resolution)
    i, j, inside = _cells_of(grid, dense)
    usable = inside.copy()
    usable[inside] = grid.costs[j[inside], i[inside]] != NO_INFORMATION
    if not usable.any():
        return i[:0], j[:0]
    start = int(np.argmax(usable))
    gaps = np.flatnonzero(~usable[start:])
    stop = start + int(gaps[0]) if len(gaps) else len(usable)
    return i[start:stop], j[start:stop]


@lru_cache(maxsize=8)
def _neighbours(height: int, width: int) -> Ints:
    """(size, 4) flat indices of every cell's 4-neighbours, in increasing order (up, left,
    right, down, as CSR rows keep their columns); 0 where a neighbour is off the grid."""
    j, i = np.divmod(np.arange(height * width), width)
    steps = ((0, -1), (-1, 0), (1, 0), (0, 1))
    ni = np.stack([i + di for di, _ in steps], axis=1)
    nj = np.stack([j + dj for _, dj in steps], axis=1)
    exists = (ni >= 0) & (ni < width) & (nj >= 0) & (nj < height)
    indices: Ints = np.where(exists, nj * width + ni, 0)
    return indices


@dataclass(frozen=True)
class DistanceMap:
    """Cells' distances (in cells, 4-connected) to a set of target cells through free space.

    Obstacles the wave touched hold :attr:`obstacle_cost` and cells it never reached hold
    :attr:`unreachable_cost`, both at least :attr:`obstacle_cost` (MapGrid's values)."""

    dist: Floats
    """(H, W) distances."""

    @property
    def obstacle_cost(self) -> float:
        return float(self.dist.size)

    @property
    def unreachable_cost(self) -> float:
        return float(self.dist.size + 1)


def wavefronts(
    grid: CostGrid,
    target_sets: list[tuple[Ints, Ints]],
    *,
    passable: Bools | None = None,
) -> list[DistanceMap]:
    """The breadth-first distance maps from each set of target cells (MapGrid's
    computeTargetDistance): the wave spreads to 4-neighbours that are not lethal, inscribed
    or unknown, except cells marked ``passable`` (the robot's own footprint).

    The maps share one graph; each is one breadth-first search from a source linked to its
    targets, and a cell's distance is its depth in that search's tree."""
    height, width = grid.costs.shape
    size = height * width
    blocked = grid.costs >= INSCRIBED
    if passable is not None:
        blocked = blocked & ~passable
    free = ~blocked.ravel()
    sets = [np.unique(rows * width + columns) for columns, rows in target_sets]
    spreads = free.copy()
    for sources in sets:
        spreads[sources] = True
    neighbour = _neighbours(height, width)
    # a CSR graph built row by row (rows are cells in order): edges from cells the wave
    # spreads from into free neighbours; a last row, the root, is empty
    free_2d = free.reshape(height, width)
    spreads_2d = spreads.reshape(height, width)
    edges = np.zeros((height, width, 4), dtype=bool)  # towards _neighbours' columns
    np.logical_and(spreads_2d[1:, :], free_2d[:-1, :], out=edges[1:, :, 0])
    np.logical_and(spreads_2d[:, 1:], free_2d[:, :-1], out=edges[:, 1:, 1])
    np.logical_and(spreads_2d[:, :-1], free_2d[:, 1:], out=edges[:, :-1, 2])
    np.logical_and(spreads_2d[:-1, :], free_2d[1:, :], out=edges[:-1, :, 3])
    edge = edges.reshape(size, 4)
    indptr = np.zeros(size + 2, dtype=np.intp)
    np.cumsum(np.count_nonzero(edge, axis=1), out=indptr[1:-1])
    indptr[-1] = indptr[-2]
    indices = neighbour[edge]
    cells = csr_matrix((np.ones(len(indices), dtype=np.int8), indices, indptr), (size + 1,) * 2)
    maps = []
    for sources in sets:
        dist = np.full(size, float(size + 1))
        if len(sources):
            depth = _bfs_depth(cells, sources)
            reached = depth >= 0
            dist[reached] = depth[reached]
            # obstacles next to reached cells: MapGrid marks them when the wave looks at them
            grid_reached = reached.reshape(height, width)
            touched = np.zeros_like(grid_reached)
            touched[1:, :] |= grid_reached[:-1, :]
            touched[:-1, :] |= grid_reached[1:, :]
            touched[:, 1:] |= grid_reached[:, :-1]
            touched[:, :-1] |= grid_reached[:, 1:]
            dist[touched.ravel() & ~free & ~reached] = float(size)
        maps.append(DistanceMap(dist.reshape(height, width)))
    return maps


def _bfs_depth(cells: csr_matrix, sources: Ints) -> Ints:
    """Breadth-first distances over the cell graph from the sources (-1 where unreached);
    several sources hang off the graph's last node, the root."""
    size = cells.shape[0] - 1
    if len(sources) == 1:
        graph, start, skip = cells, int(sources[0]), 0
    else:
        indptr = cells.indptr.copy()
        indptr[-1] += len(sources)
        graph = csr_matrix(
            (
                np.ones(len(cells.indices) + len(sources), dtype=np.int8),
                np.concatenate([cells.indices, sources]),
                indptr,
            ),
            cells.shape,
        )
        start, skip = size, 1
    graph.has_sorted_indices = True
    order, parent = breadth_first_order(graph, start, directed=True, return_predecessors=True)
    # the search visits nodes level by level, so each level is the run of nodes after the
    # one before, as long as the previous level has children
    count = len(order)
    position = np.empty(size + 1, dtype=np.intp)
    position[order] = np.arange(count)
    parent_at = position[parent[order[1:]]]
    children_before = np.zeros(count + 1, dtype=np.intp)
    np.cumsum(np.bincount(parent_at, minlength=count), out=children_before[1:])
    bounds = [0, 1]
    while bounds[-1] < count:
        bounds.append(bounds[-1] + int(children_before[bounds[-1]] - children_before[bounds[-2]]))
    levels = np.repeat(np.arange(len(bounds) - 1), np.diff(bounds))
    depth = np.full(size + 1, -1, dtype=np.intp)
    depth[order[skip:]] = levels[skip:] - skip
    return depth[:size]


def wavefront(
    grid: CostGrid, targets: tuple[Ints, Ints], *, passable: Bools | None = None
) -> DistanceMap:
    """One distance map (see :func:`wavefronts`)."""
    return wavefronts(grid, [targets], passable=passable)[0]


def filled_footprint_cells(
    grid: CostGrid, x: float, y: float, yaw: float, footprint: Floats
) -> Bools:
    """(H, W) mask of the cells whose centres the footprint at the pose covers, and the
    centre cell (the cells MapGrid treats as passable because the robot is on them)."""
    mask = np.zeros(grid.costs.shape, dtype=bool)
    centre = grid.world_to_map(x, y)
    if centre is not None:
        mask[centre[1], centre[0]] = True
    if len(footprint) < 3:
        return mask
    c, s = math.cos(yaw), math.sin(yaw)
    poly = np.column_stack(
        [
            x + c * footprint[:, 0] - s * footprint[:, 1],
            y + s * footprint[:, 0] + c * footprint[:, 1],
        ]
    )
    i, j, _ = _cells_of(grid, poly)
    i0, i1 = max(0, int(i.min())), min(grid.width - 1, int(i.max()))
    j0, j1 = max(0, int(j.min())), min(grid.height - 1, int(j.max()))
    if i0 > i1 or j0 > j1:
        return mask
    ci = np.arange(i0, i1 + 1)
    cj = np.arange(j0, j1 + 1)
    px = grid.origin_x + (ci + 0.5) * grid.resolution
    py = grid.origin_y + (cj + 0.5) * grid.resolution
    gx, gy = np.meshgrid(px, py)
    inside = np.zeros(gx.shape, dtype=bool)
    ax, ay = poly[:, 0], poly[:, 1]
    bx, by = np.roll(ax, -1), np.roll(ay, -1)
    for k in range(len(poly)):
        crosses = (ay[k] > gy) != (by[k] > gy)
        with np.errstate(divide="ignore", invalid="ignore"):
            at = ax[k] + (gy - ay[k]) * (bx[k] - ax[k]) / (by[k] - ay[k])
        inside ^= crosses & (gx < at)
    mask[j0 : j1 + 1, i0 : i1 + 1] |= inside
    return mask


def used_points_cost(
    model: FootprintModel,
    grid: CostGrid,
    r_x: Floats,
    r_y: Floats,
    r_yaw: Floats,
    used: Bools,
    scale: Floats | None = None,
) -> tuple[Floats, Bools]:
    """:meth:`FootprintModel.cost` of the used points of padded (S, N) rollouts only; the
    padding costs 0 and is valid."""
    cost = np.zeros(r_x.shape)
    valid = np.ones(r_x.shape, dtype=bool)
    grow = None if scale is None else scale[used]
    cost[used], valid[used] = model.cost(grid, r_x[used], r_y[used], r_yaw[used], scale=grow)
    return cost, valid


class FootprintModel:
    """The footprint's cost at many poses at once, as base_local_planner's CostmapModel
    scores it: a polygon (3+ points) is laid down by its outline, which must not touch a
    lethal or unknown cell nor leave the grid; a smaller footprint is a circle, whose centre
    cell must not be lethal, inscribed or unknown. Valid poses cost the highest cell cost
    met."""

    def __init__(self, footprint: Floats, resolution: float) -> None:
        self.footprint = np.asarray(footprint, dtype=np.float64).reshape(-1, 2)
        self.resolution = resolution
        self.polygon = len(self.footprint) >= 3
        if self.polygon:
            # the closed outline sampled a cell apart, as densely as its rasterised edges
            closed = np.vstack([self.footprint, self.footprint[:1]])
            outline = _densify(closed, resolution)[:-1]
        else:
            outline = np.zeros((1, 2))
        self.outline = outline
        self.radius = float(np.hypot(outline[:, 0], outline[:, 1]).max())
        # rows (1, x, y) in cells: a pose's row (centre, cos, -sin) times this is the
        # outline's columns, (centre, sin, cos) times it its rows
        self._basis = np.ascontiguousarray(
            np.vstack([np.ones(len(outline)), outline.T / resolution])
        )

    def cost(
        self,
        grid: CostGrid,
        x: Floats,
        y: Floats,
        yaw: Floats,
        *,
        scale: Floats | None = None,
    ) -> tuple[Floats, Bools]:
        """(cost, valid) of the footprint at poses of any shape; ``scale`` (same shape) grows
        the polygon about its centre."""
        shape = np.shape(x)
        px = (np.ravel(x) - grid.origin_x) / grid.resolution
        py = (np.ravel(y) - grid.origin_y) / grid.resolution
        inside = (px >= 0) & (px < grid.width) & (py >= 0) & (py < grid.height)
        if not self.polygon:
            i = np.clip(np.floor(px), 0, grid.width - 1).astype(np.intp)
            j = np.clip(np.floor(py), 0, grid.height - 1).astype(np.intp)
            cell = grid.costs[j, i]
            valid = inside & (cell < INSCRIBED)
            return cell.astype(np.float64).reshape(shape), valid.reshape(shape)
        grow = np.ones(px.shape) if scale is None else np.ravel(scale)
        # a margin of unknown cells around the grid takes the outline wherever the centre
        # is in the grid; centres outside are invalid anyway and are moved in to look up
        margin = math.ceil(self.radius * float(grow.max(initial=1.0)) / grid.resolution) + 2
        padded = np.pad(grid.costs, margin, constant_values=NO_INFORMATION)
        stride = padded.shape[1]
        cx = np.clip(px, 0, grid.width - 1e-6) + margin
        cy = np.clip(py, 0, grid.height - 1e-6) + margin
        c = np.cos(np.ravel(yaw)) * grow
        s = np.sin(np.ravel(yaw)) * grow
        # einsum, not a BLAS product: threaded BLAS is many times slower on small, loaded
        # machines for this (n, 3) x (3, k) shape
        # (truncation is the floor here: the margin keeps every coordinate positive)
        cols = np.einsum("nk,kp->np", np.column_stack([cx, c, -s]), self._basis)
        rows = np.einsum("nk,kp->np", np.column_stack([cy, s, c]), self._basis)
        flat = rows.astype(np.int32) * np.int32(stride) + cols.astype(np.int32)
        cell = np.take(padded.ravel(), flat)
        valid = inside & ~(cell >= LETHAL).any(axis=1)
        return cell.max(axis=1).astype(np.float64).reshape(shape), valid.reshape(shape)


def footprint_model(
    model: FootprintModel | None, footprint: Floats, resolution: float
) -> FootprintModel:
    """The model of ``footprint`` at ``resolution``: ``model`` itself when it is that one
    (planners keep theirs from cycle to cycle)."""
    footprint = np.asarray(footprint, dtype=np.float64).reshape(-1, 2)
    if (
        model is None
        or model.footprint.shape != footprint.shape
        or not np.array_equal(model.footprint, footprint)
        or model.resolution != resolution
    ):
        model = FootprintModel(footprint, resolution)
    return model
