"""The pose's uncertainty as GMapping estimates its proposal: the scan's likelihood at a lattice
of poses around its match, and the weighted covariance of those poses.

GMapping's scan matcher estimates the Gaussian around a match (the proposal of Grisetti et
al.'s improved particle filter) by evaluating the scan's likelihood at every pose of a small
lattice around it — x and y from ``-llsamplerange`` to ``+llsamplerange`` in steps of
``llsamplestep``, the heading from ``-lasamplerange`` to ``+lasamplerange`` in steps of
``lasamplestep`` — and taking the mean and covariance of those poses, each weighted by its
likelihood. A beam's log-likelihood is minus the squared distance from its end point to the
mean hit of the nearest occupied cell within the kernel, over ``lsigma``; a beam with no such
cell counts as if it were √0.5 m away (GMapping's "no hit": ``-0.5 / lsigma``). A pose's
log-likelihood is the sum over the beams used for matching. ``ogain`` divides the
log-likelihoods before they become weights (GMapping's gain "for smoothing the resampling
effects"; it divides by the number of particles too, which is 1 here), so a larger one
flattens them.

Here the lattice is laid in the submap's axes (the covariance is then turned into the map's),
and the squared distance is read off the likelihood field the scan was matched against: each
cell stamps ``w · exp(-d² / (2 sigma²))`` around it (``d`` the distance to the mean of its
points, ``w`` how often its wall was seen, at most 1) and the field keeps the largest stamp,
so ``-2 sigma² ln F`` is the squared distance to the nearest mean, a wall seen only once
reading a little farther. Where the field is 0 (no wall within its reach, ``kernelSize + 2``
cells) or the distance is beyond √0.5 m, the beam is a no-hit. ``lsigma`` and ``ogain`` act
only through their product: both set how steeply the weights fall off away from the match.

An axis the lattice samples at one value only (its range 0, or smaller than its step) says
nothing about that axis: its variance (and its covariance with other such axes) are taken
from the match's own least-squares estimate instead, uncorrelated with the sampled axes.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from belvedere.nav.slam._grid import FieldGrid

__all__ = ["NO_HIT", "lattice", "log_likelihoods", "sampled_covariance"]

Array = npt.NDArray[np.float64]

NO_HIT = 0.5
"""The squared distance (m²) a beam with no occupied cell near its end point counts as
(GMapping's null likelihood, -0.5, before it is divided by ``lsigma``)."""

_CHUNK = 1 << 18
"""End points evaluated at once (bounds the memory a wide lattice takes)."""


def lattice(half_range: float, step: float) -> Array:
    """Offsets ``k · step`` for ``k = -n … n``, ``n = ⌊half_range / step⌋``: symmetric about 0
    and through it (the match itself is always a sample)."""
    n = math.floor(half_range / step + 1e-9)
    return np.arange(-n, n + 1, dtype=np.float64) * step


def log_likelihoods(
    grid: FieldGrid, points: Array, poses: Array, *, sigma: float, lsigma: float
) -> Array:
    """The log-likelihood of ``points`` (N, 2) (the scan's frame) at each of ``poses`` (P, 3)
    (the grid's frame), GMapping's way (see the module's docstring): (P,)."""
    out = np.empty(len(poses))
    per_chunk = max(_CHUNK // max(len(points), 1), 1)
    px, py = points[:, 0], points[:, 1]
    for start in range(0, len(poses), per_chunk):
        chunk = poses[start : start + per_chunk]
        c = np.cos(chunk[:, 2])[:, None]
        s = np.sin(chunk[:, 2])[:, None]
        x = c * px - s * py + chunk[:, 0:1]
        y = s * px + c * py + chunk[:, 1:2]
        value, _ = grid.sample_xy(x.reshape(-1), y.reshape(-1))
        with np.errstate(divide="ignore"):
            d2 = np.where(value > 0.0, -2.0 * sigma * sigma * np.log(value), np.inf)
        d2 = np.minimum(d2, NO_HIT).reshape(len(chunk), -1)
        out[start : start + len(chunk)] = -d2.sum(axis=1) / lsigma
    return out


def sampled_covariance(
    grid: FieldGrid,
    points: Array,
    pose: Array,
    *,
    sigma: float,
    lsigma: float,
    ogain: float,
    linear: tuple[float, float],
    angular: tuple[float, float],
    fallback: Array,
) -> Array:
    """The covariance (3, 3) of the poses of the lattice around ``pose`` (the grid's frame),
    weighted by ``exp((l - l_max) / ogain)``; ``linear`` and ``angular`` are the lattice's
    (range, step); axes it samples once take their part of ``fallback``."""
    axes = (lattice(*linear), lattice(*linear), lattice(*angular))
    grid_x, grid_y, grid_t = np.meshgrid(*axes, indexing="ij")
    offsets = np.stack([grid_x.reshape(-1), grid_y.reshape(-1), grid_t.reshape(-1)], axis=1)
    sampled = np.array([len(a) > 1 for a in axes])
    cov = np.zeros((3, 3))
    if sampled.any():
        log_l = log_likelihoods(grid, points, pose + offsets, sigma=sigma, lsigma=lsigma)
        weights = np.exp((log_l - log_l.max()) / ogain)
        total = float(weights.sum())  # at least 1: the best pose weighs 1
        mean = weights @ offsets / total
        spread = offsets - mean
        cov = (spread * weights[:, None]).T @ spread / total
    alone = ~sampled
    cov[alone, :] = 0.0
    cov[:, alone] = 0.0
    cov[np.ix_(alone, alone)] = fallback[np.ix_(alone, alone)]
    return cov
