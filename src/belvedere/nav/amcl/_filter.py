"""amcl's particle filter (its ``pf.c``) over arrays: weights, KLD-adaptive resampling with
random particles injected when the weights' short-term average falls below the long-term one,
clusters over the histogram bins, and the estimate amcl publishes.

The KLD bound: drawing particles one at a time, each into a histogram bin of 0.5 m x 0.5 m x
10°, the draw stops once there are more particles than ``ceil((k-1)/(2·kld_err)·(1 - 2/(9(k-1))
+ sqrt(2/(9(k-1)))·kld_z)³)`` for ``k`` bins in use (within ``[min, max]``). Here all
``max``
candidates are drawn together and the stopping point is found on the running count of bins.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

__all__ = ["BIN_SIZE", "Cluster", "ParticleFilter", "resample_limit"]

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]

BIN_SIZE = (0.5, 0.5, math.radians(10.0))
"""The histogram's bins (x m, y m, yaw rad), as amcl's kd-tree keys them."""

DIST_THRESHOLD = 0.5
"""Converged: every particle within this of their mean in x and in y (amcl's pf)."""

_DENSE_BINS = 2_000_000
"""Up to this many bins in the particles' bounding box, bins are counted and clustered on a
dense array; beyond it, on the sorted bins."""

_NEIGHBOURS = np.ones((3, 3, 3), dtype=bool)

Headings = tuple[Floats, Floats]
"""Cosines and sines of the particles' yaws."""

RandomPoses = Callable[[int, np.random.Generator], Floats]


@dataclass(frozen=True)
class Cluster:
    """One cluster of neighbouring bins: its total weight, mean pose and covariance (3x3)."""

    weight: float
    mean: Floats
    cov: Floats
    count: int


def resample_limit(k: Ints | int, err: float, z: float, lo: int, hi: int) -> Ints:
    """How many particles ``k`` occupied bins call for (amcl's ``pf_resample_limit``)."""
    k_arr = np.asarray(k, dtype=np.float64)
    km1 = np.maximum(k_arr - 1.0, 1.0)
    b = 2.0 / (9.0 * km1)
    x = 1.0 - b + np.sqrt(b) * z
    n = np.ceil(km1 / (2.0 * err) * x * x * x)
    out = np.clip(n, lo, hi)
    return np.where(k_arr <= 1, hi, out).astype(np.int64)


def bin_keys(poses: Floats) -> Ints:
    """(3, N) integer bin keys of poses (one row per axis: reductions along rows are fast)."""
    size = np.asarray(BIN_SIZE)[:, None]
    keys: Ints = np.floor(poses.T / size).astype(np.int64, order="C")
    return keys


def _encode(keys: Ints) -> tuple[Ints, tuple[int, int, int], Ints]:
    """Keys (3, N) as one integer each over their bounding box grown by one bin, with the
    box's dimensions and lower corner (so the 26 neighbours of any key encode without
    clashing)."""
    low = keys.min(axis=1) - 1
    dims = keys.max(axis=1) - low + 2
    codes = ((keys[0] - low[0]) * dims[1] + (keys[1] - low[1])) * dims[2] + (keys[2] - low[2])
    return codes, (int(dims[0]), int(dims[1]), int(dims[2])), low


class ParticleFilter:
    """Particles ``poses`` (N, 3) with ``weights`` (N,) summing to one."""

    def __init__(
        self,
        min_samples: int,
        max_samples: int,
        *,
        alpha_slow: float,
        alpha_fast: float,
        random_poses: RandomPoses,
        rng: np.random.Generator,
        pop_err: float = 0.01,
        pop_z: float = 3.0,
        selective_resampling: bool = False,
    ) -> None:
        self.min_samples = min_samples
        self.max_samples = max_samples
        self.alpha_slow = alpha_slow
        self.alpha_fast = alpha_fast
        self.random_poses = random_poses
        self.rng = rng
        self.pop_err = pop_err
        self.pop_z = pop_z
        self.selective_resampling = selective_resampling
        self.poses: Floats = np.zeros((max_samples, 3))
        self.weights: Floats = np.full(max_samples, 1.0 / max_samples)
        self.w_slow = 0.0
        self.w_fast = 0.0
        self.n_effective = 0.0
        self.converged = False
        self.clusters: list[Cluster] = []
        self.mean: Floats = np.zeros(3)
        self.cov: Floats = np.zeros((3, 3))

    @property
    def count(self) -> int:
        return len(self.poses)

    # --- initialising ------------------------------------------------------------------------
    def init_gaussian(self, mean: npt.ArrayLike, cov: npt.ArrayLike) -> None:
        """``max_samples`` particles drawn about ``mean`` with covariance ``cov`` (3x3)."""
        mu = np.asarray(mean, dtype=np.float64)
        values, vectors = np.linalg.eigh(np.asarray(cov, dtype=np.float64))
        spread = np.sqrt(np.maximum(values, 0.0))
        noise = self.rng.standard_normal((self.max_samples, 3)) * spread
        self._reset(mu + noise @ vectors.T)

    def init_model(self) -> None:
        """``max_samples`` particles from the random pose generator (global localization)."""
        self._reset(self.random_poses(self.max_samples, self.rng))

    def _reset(self, poses: Floats) -> None:
        self.poses = poses
        self.weights = np.full(len(poses), 1.0 / len(poses))
        self.w_slow = self.w_fast = 0.0
        self.update_clusters()
        self.converged = False

    # --- updates -----------------------------------------------------------------------------
    def update_sensor(self, factors: Floats) -> None:
        """Multiply the weights by the sensor model's ``factors``, normalise, and follow the
        average likelihood's short- and long-term means (Probabilistic Robotics p. 258)."""
        weights = self.weights * factors
        total = float(weights.sum())
        if total > 0.0:
            w_avg = total / len(weights)
            self.weights = weights / total
            self.w_slow = (
                w_avg
                if self.w_slow == 0.0
                else (self.w_slow + self.alpha_slow * (w_avg - self.w_slow))
            )
            self.w_fast = (
                w_avg
                if self.w_fast == 0.0
                else (self.w_fast + self.alpha_fast * (w_avg - self.w_fast))
            )
            self.n_effective = 1.0 / float(np.dot(self.weights, self.weights))
        else:
            self.weights = np.full(len(weights), 1.0 / len(weights))
            self.n_effective = float("inf")  # amcl divides by a zero sum here

    def resample(self, headings: Headings | None = None) -> None:
        """Draw the next particle set (see the module's description). ``headings``: the
        cosines and sines of the particles' yaws, if the caller has them."""
        if self.selective_resampling and self.n_effective > 0.5 * self.count:
            self.update_clusters(headings=headings)
            return
        w_diff = 1.0 - self.w_fast / self.w_slow if self.w_slow > 0.0 else 0.0
        w_diff = max(w_diff, 0.0)
        m = self.max_samples
        cumulative = np.cumsum(self.weights)
        cumulative /= cumulative[-1]
        draws = self.rng.random(m)
        # searching sorted draws is twice as fast; each keeps its place in the draw order
        order = np.argsort(draws)
        picks = np.empty(m, dtype=np.int64)
        picks[order] = np.searchsorted(cumulative, draws[order], side="right")
        np.minimum(picks, self.count - 1, out=picks)
        candidates = self.poses.take(picks, axis=0)
        trig = None if headings is None else (headings[0].take(picks), headings[1].take(picks))
        if w_diff > 0.0:
            injected = self.rng.random(m) < w_diff
            n_random = int(injected.sum())
            if n_random:
                candidates[injected] = self.random_poses(n_random, self.rng)
                if trig is not None:
                    trig[0][injected] = np.cos(candidates[injected, 2])
                    trig[1][injected] = np.sin(candidates[injected, 2])
        keys = bin_keys(candidates)
        codes, dims, _ = _encode(keys)
        order = np.arange(m)
        if dims[0] * dims[1] * dims[2] <= _DENSE_BINS:
            first_at = np.full(dims[0] * dims[1] * dims[2], m)
            np.minimum.at(first_at, codes, order)
            new_bin = first_at[codes] == order
        else:
            _, first = np.unique(codes, return_index=True)
            new_bin = np.zeros(m, dtype=bool)
            new_bin[first] = True
        bins = np.cumsum(new_bin)
        # the bound for each count of bins, once, rather than once per candidate
        bound = resample_limit(
            np.arange(bins[-1] + 1), self.pop_err, self.pop_z, self.min_samples, m
        )
        limits = bound[bins]
        # amcl stops right after the draw that takes the count past the limit
        over = np.nonzero(np.arange(1, m + 1) > limits)[0]
        count = int(over[0]) + 1 if len(over) else m
        self.poses = candidates[:count]
        self.weights = np.full(count, 1.0 / count)
        if w_diff > 0.0:
            self.w_slow = self.w_fast = 0.0
        # the kept candidates' bins, already encoded when they are all kept (else in the
        # smaller box of those kept, as a larger one would cost more to label)
        self.update_clusters(
            keys[:, :count],
            (codes, dims) if count == m else None,
            None if trig is None else (trig[0][:count], trig[1][:count]),
        )
        self._update_converged()

    def _update_converged(self) -> None:
        x, y = np.ascontiguousarray(self.poses[:, :2].T)
        n = len(x)
        # the mean as poses[:, :2].mean(axis=0) has it (that reduction adds row after row,
        # as a running sum does) without its slow strided pass
        mean_x, mean_y = float(np.cumsum(x)[-1]) / n, float(np.cumsum(y)[-1]) / n
        # rounding is monotonic, so the extremes decide exactly as every particle would
        spread = (x.max() - mean_x, mean_x - x.min(), y.max() - mean_y, mean_y - y.min())
        self.converged = bool(np.max(spread) <= DIST_THRESHOLD)  # np.max: a NaN is not

    # --- statistics --------------------------------------------------------------------------
    def update_clusters(
        self,
        keys: Ints | None = None,
        encoded: tuple[Ints, tuple[int, int, int]] | None = None,
        headings: Headings | None = None,
    ) -> None:
        """Clusters of the particles' bins (bins touching in x, y and yaw, diagonals too),
        each with its weight, mean and covariance, and the whole set's mean and covariance.
        ``keys``/``encoded``/``headings``: the particles' ``bin_keys``, their ``_encode`` and
        the cosines and sines of their yaws, when the caller has them."""
        poses, weights = self.poses, self.weights
        if encoded is not None:
            codes, dims = encoded
        else:
            codes, dims, _ = _encode(bin_keys(poses) if keys is None else keys)
        if dims[0] * dims[1] * dims[2] <= _DENSE_BINS:
            filled = np.zeros(dims[0] * dims[1] * dims[2], dtype=bool)
            filled[codes] = True
            labels, n_clusters = ndimage.label(filled.reshape(dims), structure=_NEIGHBOURS)
            label = labels.ravel()[codes] - 1
        else:
            label, n_clusters = _sparse_labels(codes, dims)
        if headings is None:
            headings = np.cos(poses[:, 2]), np.sin(poses[:, 2])
        stats = _weighted_stats(poses, weights, headings, label, n_clusters)
        self.clusters = stats[:-1]
        whole = stats[-1]
        self.mean, self.cov = whole.mean, whole.cov

    def best_cluster(self) -> Cluster | None:
        """The heaviest cluster (amcl publishes its mean), None if no cluster has weight."""
        best = max(self.clusters, key=lambda c: c.weight, default=None)
        return best if best is not None and best.weight > 0.0 else None


def _sparse_labels(codes: Ints, dims: tuple[int, int, int]) -> tuple[Ints, int]:
    """Cluster labels of encoded bins too spread for a dense box: neighbours found by
    searching the sorted bins, components by a sparse graph."""
    unique, inverse = np.unique(codes, return_inverse=True)
    k = len(unique)
    rows: list[Ints] = []
    cols: list[Ints] = []
    stride = (dims[1] * dims[2], dims[2], 1)
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dth in (-1, 0, 1):
                offset = dx * stride[0] + dy * stride[1] + dth * stride[2]
                if offset <= 0:
                    continue  # each pair once
                target = unique + offset
                at = np.minimum(np.searchsorted(unique, target), k - 1)
                found = unique[at] == target
                rows.append(np.nonzero(found)[0])
                cols.append(at[found])
    edges_from = np.concatenate(rows)
    edges_to = np.concatenate(cols)
    graph = coo_matrix((np.ones(len(edges_from)), (edges_from, edges_to)), shape=(k, k))
    n_clusters, labels = connected_components(graph, directed=False)
    label: Ints = labels[inverse]
    return label, int(n_clusters)


def _weighted_stats(
    poses: Floats, weights: Floats, headings: Headings, label: Ints, n: int
) -> list[Cluster]:
    """Per-cluster statistics, then the whole set's as the last entry (pf's sums: linear
    covariance from the second moments, the angle's from the mean resultant length, which
    pf.c leaves unnormalised by a cluster's weight — over the whole set the weights sum to
    one)."""
    x, y = np.ascontiguousarray(poses[:, :2].T)
    rows = np.empty((8, len(x)))
    rows[0] = weights
    np.multiply(weights, x, out=rows[1])
    np.multiply(weights, y, out=rows[2])
    np.multiply(weights, headings[0], out=rows[3])
    np.multiply(weights, headings[1], out=rows[4])
    np.multiply(rows[1], x, out=rows[5])
    np.multiply(rows[1], y, out=rows[6])
    np.multiply(rows[2], y, out=rows[7])
    whole = rows.sum(axis=1)
    if n == 1:
        per = whole[None, :]
        count = np.array([len(x), len(x)])
    else:
        per = np.stack([np.bincount(label, weights=row, minlength=n) for row in rows], axis=1)
        count = np.append(np.bincount(label, minlength=n), len(x))
    table = np.vstack([per, whole])  # (n + 1, 8)
    w, mx, my, mc, ms, cxx, cxy, cyy = table.T
    with np.errstate(divide="ignore", invalid="ignore"):
        mean = np.stack([mx / w, my / w, np.arctan2(ms, mc)], axis=1)
        cov = np.zeros((n + 1, 3, 3))
        cov[:, 0, 0] = cxx / w - mean[:, 0] ** 2
        cov[:, 0, 1] = cov[:, 1, 0] = cxy / w - mean[:, 0] * mean[:, 1]
        cov[:, 1, 1] = cyy / w - mean[:, 1] ** 2
        cov[:, 2, 2] = -2.0 * np.log(np.hypot(mc, ms))
    return [Cluster(float(w[i]), mean[i], cov[i], int(count[i])) for i in range(n + 1)]
