"""global_planner's ``AStarExpansion`` and its ``clearEndpoint``, cell by cell.

A* here is global_planner's, not a textbook one: a cell's potential is set once, when a
neighbour being expanded first reaches it, by the planner's potential calculator (the
quadratic one with ``use_quadratic``, reading the cell's four neighbours as they are at that
moment; else the expanding cell's potential plus the step). The queue is ordered by that
potential plus the Manhattan distance to the goal times ``neutral_cost``, and the search ends
when the goal cell leaves the queue. The step handed to the calculator is the cell's cost plus
``neutral_cost`` in an ``unsigned char``, as in ROS, so it wraps past 255: a cell of cost 206
or more (with the default ``neutral_cost`` 50) is cheap to enter (ros-planning/navigation#784,
never fixed in ROS 1).
"""

from __future__ import annotations

import heapq
import itertools

import numpy as np
import numpy.typing as npt

from belvedere.nav.planners._wavefront import POT_HIGH, Field

__all__ = ["astar", "clear_endpoint", "step_costs"]

_POT_HIGH = float(np.float32(POT_HIGH))


def step_costs(costs: npt.NDArray[np.uint8], neutral: int) -> npt.NDArray[np.uint8]:
    """Each cell's step as the calculators receive it: ``cost + neutral`` in 8 bits."""
    stepped: npt.NDArray[np.uint8] = ((costs.astype(np.int64) + neutral) % 256).astype(np.uint8)
    return stepped


def _potential(pot: list[float], n: int, stride: int, step: float, quadratic: bool) -> float:
    """The potential calculator with no previous potential given: from the lowest neighbours
    (quadratic: navfn's interpolation between the lower horizontal and vertical one)."""
    left, right, up, down = pot[n - 1], pot[n + 1], pot[n - stride], pot[n + stride]
    if not quadratic:
        return min(left, right, up, down) + step
    tc = min(left, right)
    ta = min(up, down)
    dc = tc - ta
    if dc < 0:
        dc, ta = -dc, tc
    if dc >= step:
        return ta + step
    d = dc / step
    return ta + step * (-0.2301 * d * d + 0.5307 * d + 0.7040)


def astar(
    costs: npt.NDArray[np.uint8],
    passable: npt.NDArray[np.bool_],
    start: tuple[int, int],
    goal: tuple[int, int],
    *,
    neutral: int,
    quadratic: bool,
) -> Field | None:
    """Potentials (H, W) of the cells A* reached from ``start`` (column, row), POT_HIGH
    elsewhere; None when the goal cell was never expanded. ``passable`` says where the search
    may go; the outermost ring is never entered."""
    height, width = costs.shape
    stride = width
    ok = np.ascontiguousarray(passable, dtype=bool).copy()
    ok[0, :] = ok[-1, :] = ok[:, 0] = ok[:, -1] = False
    allowed = ok.ravel().tolist()
    steps = step_costs(costs, neutral).ravel().tolist()
    pot = [_POT_HIGH] * (height * width)
    src = start[1] * stride + start[0]
    target = goal[1] * stride + goal[0]
    gx, gy = goal
    pot[src] = 0.0
    order = itertools.count()
    queue: list[tuple[float, int, int]] = [(0.0, next(order), src)]
    found = False
    while queue:
        _, _, i = heapq.heappop(queue)
        if i == target:
            found = True
            break
        here = pot[i]
        for n in (i + 1, i - 1, i + stride, i - stride):
            if pot[n] < _POT_HIGH or not allowed[n]:
                continue
            step = float(steps[n])
            # the quadratic calculator ignores the expanding cell's potential
            value = _potential(pot, n, stride, step, quadratic=True) if quadratic else here + step
            value = float(np.float32(value))
            pot[n] = value
            distance = abs(gx - n % stride) + abs(gy - n // stride)
            heapq.heappush(queue, (value + distance * neutral, next(order), n))
    if not found:
        return None
    return np.array(pot, dtype=np.float32).reshape(height, width)


def clear_endpoint(
    costs: npt.NDArray[np.uint8],
    pot: Field,
    goal: tuple[int, int],
    *,
    neutral: int,
    quadratic: bool,
    size: int = 2,
) -> None:
    """``clearEndpoint``: the cells within ``size`` of the goal cell that the wave did not
    reach get a potential from their neighbours (column by column, each seeing the ones set
    before it), so the path can start at a goal a little inside an obstacle."""
    height, width = pot.shape
    steps = step_costs(costs, neutral)
    for di in range(-size, size + 1):
        for dj in range(-size, size + 1):
            i, j = goal[0] + di, goal[1] + dj
            if not (0 < i < width - 1 and 0 < j < height - 1) or pot[j, i] < POT_HIGH:
                continue
            # the four neighbours laid out as _potential reads them: index 2, stride 2
            around = [
                float(pot[j - 1, i]),
                float(pot[j, i - 1]),
                _POT_HIGH,
                float(pot[j, i + 1]),
                float(pot[j + 1, i]),
            ]
            value = _potential(around, 2, 2, float(steps[j, i]), quadratic)
            pot[j, i] = np.float32(min(value, POT_HIGH))
