"""Paths down a potential field: navfn's gradient descent and global_planner's grid walk.

Both walk from the goal cell down to the cell where the potential is zero (the robot's), in
cell coordinates (column, row as floats); the planners reverse and convert them.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from belvedere.nav.planners._wavefront import POT_HIGH, Field

__all__ = ["gradient_path", "grid_path"]

_STEP = 0.5
"""navfn's ``pathStep``: half a cell per gradient step."""

_OBSTACLE_PULL = 254.0
"""The gradient out of an unreached cell toward a reached neighbour (navfn's ``COST_OBS``)."""


def _gradient(
    pot: Field, i: int, j: int, cache: dict[tuple[int, int], tuple[float, float]]
) -> tuple[float, float]:
    """The normalised downhill direction at cell (i, j), as navfn's ``gradCell`` computes it."""
    key = (i, j)
    if key in cache:
        return cache[key]
    height, width = pot.shape
    dx = dy = 0.0
    if 0 < i < width - 1 and 0 < j < height - 1:
        cv = float(pot[j, i])
        left, right = float(pot[j, i - 1]), float(pot[j, i + 1])
        down, up = float(pot[j - 1, i]), float(pot[j + 1, i])
        if cv >= POT_HIGH:
            if left < POT_HIGH:
                dx = -_OBSTACLE_PULL
            elif right < POT_HIGH:
                dx = _OBSTACLE_PULL
            if down < POT_HIGH:
                dy = -_OBSTACLE_PULL
            elif up < POT_HIGH:
                dy = _OBSTACLE_PULL
        else:
            if left < POT_HIGH:
                dx += left - cv
            if right < POT_HIGH:
                dx += cv - right
            if down < POT_HIGH:
                dy += down - cv
            if up < POT_HIGH:
                dy += cv - up
    norm = math.hypot(dx, dy)
    result = (dx / norm, dy / norm) if norm > 0 else (0.0, 0.0)
    cache[key] = result
    return result


def gradient_path(
    pot: Field, goal: tuple[int, int], *, stop_below: float, max_steps: int
) -> npt.NDArray[np.float64] | None:
    """navfn's ``calcPath``: half-cell steps along the interpolated gradient from ``goal``,
    falling back to the lowest of the eight neighbours where one is unreached or the walk
    oscillates; ends (with the zero-potential cell appended) once the potential is below
    ``stop_below``. None when it runs into a dead end or ``max_steps``."""
    height, width = pot.shape
    ci, cj = goal
    dx = dy = 0.0
    xs: list[float] = []
    ys: list[float] = []
    cache: dict[tuple[int, int], tuple[float, float]] = {}
    zero = np.unravel_index(int(np.argmin(pot)), pot.shape)
    for _ in range(max_steps):
        ni = min(max(ci + round(dx), 0), width - 1)
        nj = min(max(cj + round(dy), 0), height - 1)
        if pot[nj, ni] < stop_below:
            xs.append(float(zero[1]))
            ys.append(float(zero[0]))
            return np.column_stack([xs, ys])
        if not (0 < ci < width - 1 and 0 < cj < height - 1):
            return None
        xs.append(ci + dx)
        ys.append(cj + dy)
        oscillating = len(xs) > 2 and xs[-1] == xs[-3] and ys[-1] == ys[-3]
        window = pot[cj - 1 : cj + 2, ci - 1 : ci + 2]
        if oscillating or bool((window >= POT_HIGH).any()):
            # navfn scans row by row from the lower-left and keeps the first strict minimum
            flat = int(np.argmin(window))
            if window.flat[flat] < pot[cj, ci]:
                ci, cj = ci - 1 + flat % 3, cj - 1 + flat // 3
            dx = dy = 0.0
            if pot[cj, ci] >= POT_HIGH:
                return None
            continue
        gx00, gy00 = _gradient(pot, ci, cj, cache)
        gx10, gy10 = _gradient(pot, ci + 1, cj, cache)
        gx01, gy01 = _gradient(pot, ci, cj + 1, cache)
        gx11, gy11 = _gradient(pot, ci + 1, cj + 1, cache)
        gx = (1 - dy) * ((1 - dx) * gx00 + dx * gx10) + dy * ((1 - dx) * gx01 + dx * gx11)
        gy = (1 - dy) * ((1 - dx) * gy00 + dx * gy10) + dy * ((1 - dx) * gy01 + dx * gy11)
        if gx == 0.0 and gy == 0.0:
            return None
        scale = _STEP / math.hypot(gx, gy)
        dx += gx * scale
        dy += gy * scale
        if dx > 1.0:
            ci += 1
            dx -= 1.0
        if dx < -1.0:
            ci -= 1
            dx += 1.0
        if dy > 1.0:
            cj += 1
            dy -= 1.0
        if dy < -1.0:
            cj -= 1
            dy += 1.0
    return None


def grid_path(
    pot: Field, goal: tuple[int, int], *, max_steps: int
) -> npt.NDArray[np.float64] | None:
    """global_planner's ``GridPath``: from ``goal``, step to the lowest of the eight
    neighbours until the zero-potential cell; None at a dead end."""
    height, width = pot.shape
    ci, cj = goal
    cells = [(ci, cj)]
    for _ in range(max_steps):
        if pot[cj, ci] == 0.0:
            return np.array(cells, dtype=np.float64)
        best = (float(pot[cj, ci]), ci, cj)
        for dj in (-1, 0, 1):
            for di in (-1, 0, 1):
                i, j = ci + di, cj + dj
                if (di or dj) and 0 <= i < width and 0 <= j < height and pot[j, i] < best[0]:
                    best = (float(pot[j, i]), i, j)
        if best[0] >= POT_HIGH or (best[1], best[2]) == (ci, cj):
            return None
        ci, cj = best[1], best[2]
        cells.append((ci, cj))
    return None
