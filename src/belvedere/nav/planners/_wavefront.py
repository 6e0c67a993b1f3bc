"""navfn's potential propagation, vectorised: threshold-ordered wavefronts over a cost array.

navfn (and global_planner's ``DijkstraExpansion``) do not run an exact Dijkstra: cells wait in
priority buffers and are processed once their potential is below a threshold that rises by
``2 * neutral_cost`` each time the current buffer empties. Here each buffer is processed as one
numpy batch (its cells see each other's previous potentials, and any cell that improves pushes
its four neighbours again), so the potential converges to the same fixed point navfn's update
has, at numpy speed instead of one Python step per cell.
"""

from __future__ import annotations

from typing import Final

import numpy as np
import numpy.typing as npt

__all__ = ["POT_HIGH", "Field", "propagate"]

POT_HIGH: Final = 1.0e10
"""The potential of a cell the wavefront never reached (navfn's ``POT_HIGH``)."""

Field = npt.NDArray[np.float32]


def _quadratic(pot: Field, cost: Field, cells: npt.NDArray[np.intp], stride: int) -> Field:
    """navfn's update: the potential from the lower horizontal and vertical neighbours with its
    quadratic approximation of the Eikonal step (a single neighbour when they differ by more
    than the cell's cost)."""
    left = pot[cells - 1]
    right = pot[cells + 1]
    up = pot[cells - stride]
    down = pot[cells + stride]
    tc = np.minimum(left, right)
    ta = np.minimum(up, down)
    hf = cost[cells]
    low = np.minimum(ta, tc)
    dc = np.abs(tc - ta)
    d = dc / hf
    v = (-0.2301 * d + 0.5307) * d + 0.7040
    return np.where(dc >= hf, low + hf, low + hf * v).astype(np.float32)


def _simple(pot: Field, cost: Field, cells: npt.NDArray[np.intp], stride: int) -> Field:
    """global_planner's ``PotentialCalculator``: the lowest neighbour plus the cell's cost."""
    low = np.minimum(
        np.minimum(pot[cells - 1], pot[cells + 1]),
        np.minimum(pot[cells - stride], pot[cells + stride]),
    )
    return (low + cost[cells]).astype(np.float32)


def propagate(
    cost: Field,
    passable: npt.NDArray[np.bool_],
    source: tuple[int, int],
    *,
    target: tuple[int, int] | None,
    increment: float,
    quadratic: bool,
) -> Field:
    """Potentials over a grid from ``source`` (column, row); POT_HIGH where not reached.

    ``cost`` (H, W) is each cell's traversal cost, ``passable`` where the wave may enter. The
    outermost ring is never entered (navfn and ``outline_map`` make it an obstacle; here it
    also keeps neighbour indices inside the array). With a ``target`` the wave stops once the
    threshold has passed the target's potential, as navfn stops at its start cell; without one
    it covers everything reachable.
    """
    height, width = cost.shape
    stride = width
    flat_cost = np.ascontiguousarray(cost, dtype=np.float32).ravel()
    ok = np.ascontiguousarray(passable, dtype=bool).copy()
    ok[0, :] = ok[-1, :] = ok[:, 0] = ok[:, -1] = False
    flat_ok = ok.ravel()
    pot = np.full(height * width, POT_HIGH, dtype=np.float32)
    update = _quadratic if quadratic else _simple
    offsets = np.array([1, -1, stride, -stride], dtype=np.intp)
    src = source[1] * stride + source[0]
    goal = -1 if target is None else target[1] * stride + target[0]
    pot[src] = 0.0
    pending = np.zeros(height * width, dtype=bool)
    slot = np.zeros(height * width, dtype=np.intp)
    empty = np.empty(0, dtype=np.intp)

    def neighbours(cells: npt.NDArray[np.intp]) -> npt.NDArray[np.intp]:
        around = (cells[:, None] + offsets[None, :]).ravel()
        around = around[flat_ok[around] & ~pending[around]]
        # keep each cell once: the last write of its slot wins, so one copy matches
        slot[around] = np.arange(around.size)
        unique: npt.NDArray[np.intp] = around[slot[around] == np.arange(around.size)]
        pending[unique] = True
        return unique

    threshold = float(increment)
    current = neighbours(np.array([src], dtype=np.intp))
    over = empty
    while current.size or over.size:
        if current.size == 0:
            threshold += increment
            current, over = over, empty
            if goal >= 0 and pot[goal] + increment < threshold:
                break
            continue
        pending[current] = False
        new = update(pot, flat_cost, current, stride)
        better = new < pot[current]
        cells = current[better]
        pot[cells] = new[better]
        below = pot[cells] < threshold
        current = neighbours(cells[below])
        later = neighbours(cells[~below])
        if later.size:
            over = np.concatenate([over, later]) if over.size else later
    return pot.reshape(height, width)
