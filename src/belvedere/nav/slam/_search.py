"""Correlative scan matching by branch and bound over a window of poses.

For a finished grid, level ``h`` of a pyramid holds, per block of ``2^h x 2^h`` cells, the
largest field value over that block and its three neighbours towards +x/+y: every point of a
scan shifted by any offset within one block's span lands in one of those four blocks, so the
mean of those values over the scan bounds the score of every pose in the span from above.
The search keeps the spans whose bound beats the best complete score found so far, splitting
each into four at the next level down, with a greedy descent first so that pruning starts
early; every level is evaluated for all surviving spans and angles at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from belvedere.nav.slam._grid import FieldGrid

__all__ = ["SearchPyramid", "SearchResult"]

Array = npt.NDArray[np.float64]

_FRONTIER_CAP = 512
"""At most this many spans are kept per level (the best bounds): a bound on work."""


@dataclass(frozen=True)
class SearchResult:
    pose: Array
    """Pose of the scan's frame in the grid's frame (on the search lattice)."""
    score: float
    runner_up: float = 0.0
    """The best score away from the best pose (0: none above the ambiguity asked for)."""


class SearchPyramid:
    def __init__(self, grid: FieldGrid, depth: int) -> None:
        self.resolution = grid.resolution
        self.depth = depth
        base = grid.field
        # Only the part of the grid that holds any weight (plus one zero row and column, so
        # that look-ups clamped to the last row or column read 0).
        rows = np.flatnonzero(base.any(axis=1))
        cols = np.flatnonzero(base.any(axis=0))
        if len(rows):
            base = base[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1]
            offset = np.array([cols[0], rows[0]], dtype=np.float64)
        else:
            base = np.zeros((1, 1), dtype=np.float32)
            offset = np.zeros(2)
        self.origin = grid.origin + offset * grid.resolution
        level0 = np.zeros((base.shape[0] + 1, base.shape[1] + 1), dtype=np.float32)
        level0[:-1, :-1] = base
        levels = [level0]
        pooled = base
        for _ in range(depth):
            h, w = pooled.shape
            even = np.zeros((h + h % 2, w + w % 2), dtype=np.float32)
            even[:h, :w] = pooled
            pooled = even.reshape(even.shape[0] // 2, 2, even.shape[1] // 2, 2).max(axis=(1, 3))
            # One zero block in front (block -1) and two behind: entry k is block k - 1.
            h, w = pooled.shape
            p = np.zeros((h + 3, w + 3), dtype=np.float32)
            p[1 : h + 1, 1 : w + 1] = pooled
            dilated = np.maximum(
                np.maximum(p[:-1, :-1], p[1:, :-1]), np.maximum(p[:-1, 1:], p[1:, 1:])
            )
            levels.append(dilated)
        self.levels = levels

    def _bound(self, level: int, ix: npt.NDArray[np.int64], iy: npt.NDArray[np.int64]) -> Array:
        grid = self.levels[level]
        h, w = grid.shape
        if level:
            ix = (ix >> level) + 1
            iy = (iy >> level) + 1
        # The last row and column are zero: anything off the grid reads there (a negative
        # index, seen unsigned, is huge and clamps there too).
        ix = np.minimum(ix.astype(np.uint64), w - 1).astype(np.intp)
        iy = np.minimum(iy.astype(np.uint64), h - 1).astype(np.intp)
        values: Array = grid.reshape(-1)[iy * w + ix].sum(axis=-1) / ix.shape[-1]
        return values

    def search(
        self,
        points: Array,
        center: Array,
        linear_window: float,
        angular_window: float,
        angular_step: float,
        min_score: float,
        ambiguity: float | None = None,
        distinct_xy: float = 0.5,
        distinct_theta: float = 0.09,
    ) -> SearchResult | None:
        """The best pose within ``±linear_window`` (m) and ``±angular_window`` (rad) of
        ``center`` (pose in the grid's frame) for ``points`` (N, 2) in the scan's frame, if
        its score reaches ``min_score``. With ``ambiguity``, also the best score of the poses
        at least ``distinct_xy`` or ``distinct_theta`` away from it, if it reaches
        ``ambiguity`` times the best (a second peak: the scan fits two places)."""
        res = self.resolution
        half = max(math.ceil(linear_window / res), 0)
        steps = max(math.ceil(angular_window / angular_step), 0)
        angles = center[2] + np.arange(-steps, steps + 1) * angular_step
        c = np.cos(angles)[:, None]
        s = np.sin(angles)[:, None]
        px = points[None, :, 0]
        py = points[None, :, 1]
        qx = (c * px - s * py + center[0] - self.origin[0]) / res - half
        qy = (s * px + c * py + center[1] - self.origin[1]) / res - half
        cx = np.floor(qx).astype(np.int64)  # (A, N): cells at the window's corner offset
        cy = np.floor(qy).astype(np.int64)
        span = 2 * half + 1
        top = self.depth
        while top > 0 and (1 << (top - 1)) >= span:
            top -= 1
        size = 1 << top
        count = (span + size - 1) // size
        ka, kx, ky = np.meshgrid(
            np.arange(len(angles)), np.arange(count) * size, np.arange(count) * size, indexing="ij"
        )
        start = np.stack([ka.ravel(), kx.ravel(), ky.ravel()], axis=1)

        def evaluate(level: int, cand: npt.NDArray[np.int64]) -> Array:
            a = cand[:, 0]
            return self._bound(level, cx[a] + cand[:, 1:2], cy[a] + cand[:, 2:3])

        def children(level: int, cand: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
            step = 1 << (level - 1)
            out = np.repeat(cand, 4, axis=0)
            out[:, 1] += np.tile(np.array([0, step, 0, step]), len(cand))
            out[:, 2] += np.tile(np.array([0, 0, step, step]), len(cand))
            keep = (out[:, 1] < span) & (out[:, 2] < span)
            return out[keep]

        def finest(
            cand: npt.NDArray[np.int64], exclude: tuple[int, int, int, int, int] | None
        ) -> Array:
            scores = evaluate(0, cand)
            if exclude is not None:
                a0, x0, y0, da, dxy = exclude
                near = (
                    (np.abs(cand[:, 0] - a0) <= da)
                    & (np.abs(cand[:, 1] - x0) <= dxy)
                    & (np.abs(cand[:, 2] - y0) <= dxy)
                )
                scores = np.where(near, -np.inf, scores)
            return scores

        def best_of(
            floor: float, exclude: tuple[int, int, int, int, int] | None
        ) -> tuple[float, tuple[int, int, int] | None]:
            best_score = floor
            best: tuple[int, int, int] | None = None
            cand = start
            if top == 0:
                bounds = finest(cand, exclude)
                i = int(np.argmax(bounds))
                if bounds[i] > best_score:
                    return float(bounds[i]), (int(cand[i, 0]), int(cand[i, 1]), int(cand[i, 2]))
                return best_score, None
            bounds = evaluate(top, cand)
            # A greedy descent from the best span gives a first complete score to prune with.
            probe = cand[np.argsort(-bounds, kind="stable")[:1]]
            for level in range(top, 0, -1):
                kids = children(level, probe)
                kb = finest(kids, exclude) if level == 1 else evaluate(level - 1, kids)
                probe = kids[np.argmax(kb)][None, :]
                if level == 1 and kb.max() > best_score:
                    best_score = float(kb.max())
                    best = (int(probe[0, 0]), int(probe[0, 1]), int(probe[0, 2]))
            for level in range(top, 0, -1):
                keep = bounds > best_score
                cand = cand[keep]
                bounds = bounds[keep]
                if not len(cand):
                    break
                if len(cand) > _FRONTIER_CAP:
                    cand = cand[np.argsort(-bounds, kind="stable")[:_FRONTIER_CAP]]
                cand = children(level, cand)
                bounds = finest(cand, exclude) if level == 1 else evaluate(level - 1, cand)
                if level == 1 and len(bounds):
                    i = int(np.argmax(bounds))
                    if bounds[i] > best_score:
                        best_score = float(bounds[i])
                        best = (int(cand[i, 0]), int(cand[i, 1]), int(cand[i, 2]))
            return best_score, best

        score, best = best_of(min_score, None)
        if best is None:
            return None
        a, ox, oy = best
        runner_up = 0.0
        if ambiguity is not None:
            exclude = (
                a,
                ox,
                oy,
                math.ceil(distinct_theta / angular_step),
                math.ceil(distinct_xy / res),
            )
            other, found = best_of(score * ambiguity, exclude)
            runner_up = other if found is not None else 0.0
        pose = np.array([center[0] + (ox - half) * res, center[1] + (oy - half) * res, angles[a]])
        return SearchResult(pose=pose, score=score, runner_up=runner_up)
