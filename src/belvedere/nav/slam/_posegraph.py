"""A small 2D pose graph: nodes are poses ``(x, y, theta)``, edges relative measurements with
an information matrix; Gauss-Newton with a Huber kernel on each edge's Mahalanobis distance
(so that one wrong loop closure bends the graph less than a quadratic cost would). The graph
is small (one node per submap), so the normal equations are solved densely."""

from __future__ import annotations

import heapq
import itertools

import numpy as np
import numpy.typing as npt

from belvedere.nav.slam._se2 import wrap

__all__ = ["PoseGraph"]

Array = npt.NDArray[np.float64]


class PoseGraph:
    def __init__(self) -> None:
        self.poses = np.zeros((0, 3))
        self._i: list[int] = []
        self._j: list[int] = []
        self._z: list[Array] = []
        self._info: list[Array] = []
        self._robust: list[float] = []
        self._length: list[float] = []

    def add_node(self, pose: Array) -> int:
        self.poses = np.vstack([self.poses, np.asarray(pose, dtype=np.float64)[None, :]])
        return len(self.poses) - 1

    def add_edge(
        self,
        i: int,
        j: int,
        measurement: Array,
        information: Array,
        huber: float = 0.0,
        length: float | None = None,
    ) -> None:
        """``measurement`` is node ``j``'s pose seen from node ``i``; ``huber`` the Mahalanobis
        distance beyond which the cost grows linearly (0: plain least squares); ``length``
        how far apart the edge's uncertainty puts its nodes, in metres of travel (default:
        the measurement's translation) — for :meth:`distances`."""
        self._length.append(
            float(np.hypot(measurement[0], measurement[1])) if length is None else length
        )
        self._i.append(i)
        self._j.append(j)
        self._z.append(np.asarray(measurement, dtype=np.float64))
        self._info.append(np.asarray(information, dtype=np.float64))
        self._robust.append(huber)

    def remove_edge(self, index: int) -> None:
        for store in (self._i, self._j, self._z, self._info, self._robust, self._length):
            del store[index]

    def distances(self, source: int) -> Array:
        """Shortest total edge length from ``source`` to every node (inf: not connected)."""
        count = len(self.poses)
        adjacency: list[list[tuple[int, float]]] = [[] for _ in range(count)]
        for i, j, length in zip(self._i, self._j, self._length, strict=True):
            adjacency[i].append((j, length))
            adjacency[j].append((i, length))
        dist = np.full(count, np.inf)
        dist[source] = 0.0
        queue = [(0.0, source)]
        while queue:
            d, node = heapq.heappop(queue)
            if d > dist[node]:
                continue
            for other, length in adjacency[node]:
                nd = d + length
                if nd < dist[other]:
                    dist[other] = nd
                    heapq.heappush(queue, (nd, other))
        return dist

    @property
    def edge_count(self) -> int:
        return len(self._i)

    def errors(self) -> Array:
        """Each edge's Mahalanobis distance at the current poses."""
        e, _, _, info = self._linearize()
        squared = np.einsum("ni,nij,nj->n", e, info, e)
        return np.asarray(np.sqrt(np.maximum(squared, 0.0)), dtype=np.float64)

    def cost(self) -> float:
        """The sum of every edge's squared Mahalanobis distance at the current poses (no
        robust kernel): the graph's χ²."""
        if not self._i:
            return 0.0
        return float(np.sum(self.errors() ** 2))

    def _linearize(self) -> tuple[Array, Array, Array, Array]:
        i = np.asarray(self._i)
        j = np.asarray(self._j)
        z = np.asarray(self._z)
        info = np.asarray(self._info)
        pi = self.poses[i]
        pj = self.poses[j]
        ci, si = np.cos(pi[:, 2]), np.sin(pi[:, 2])
        cz, sz = np.cos(z[:, 2]), np.sin(z[:, 2])
        dx = pj[:, 0] - pi[:, 0]
        dy = pj[:, 1] - pi[:, 1]
        # Node j in node i's frame, then its difference from the measurement in z's frame.
        lx = ci * dx + si * dy
        ly = -si * dx + ci * dy
        ex = cz * (lx - z[:, 0]) + sz * (ly - z[:, 1])
        ey = -sz * (lx - z[:, 0]) + cz * (ly - z[:, 1])
        et = wrap(pj[:, 2] - pi[:, 2] - z[:, 2])
        e = np.stack([ex, ey, et], axis=1)
        n = len(i)
        # d(l)/d(t_i) = -R_iᵀ, d(l)/d(theta_i) = dR_iᵀ/dθ · (t_j - t_i) = (ly, -lx).
        rz = np.zeros((n, 2, 2))
        rz[:, 0, 0] = cz
        rz[:, 0, 1] = sz
        rz[:, 1, 0] = -sz
        rz[:, 1, 1] = cz
        ri = np.zeros((n, 2, 2))
        ri[:, 0, 0] = ci
        ri[:, 0, 1] = si
        ri[:, 1, 0] = -si
        ri[:, 1, 1] = ci
        rr = rz @ ri
        a = np.zeros((n, 3, 3))
        b = np.zeros((n, 3, 3))
        a[:, :2, :2] = -rr
        a[:, :2, 2] = np.einsum("nij,nj->ni", rz, np.stack([ly, -lx], axis=1))
        a[:, 2, 2] = -1.0
        b[:, :2, :2] = rr
        b[:, 2, 2] = 1.0
        return e, a, b, info

    def optimize(self, iterations: int = 10, fixed: int = 0) -> float:
        """Gauss-Newton with node ``fixed`` held still; returns the final cost."""
        if not self._i:
            return 0.0
        count = len(self.poses)
        i = np.asarray(self._i, dtype=np.intp)
        j = np.asarray(self._j, dtype=np.intp)
        huber = np.asarray(self._robust)
        cost = 0.0
        for _ in range(iterations):
            e, a, b, info = self._linearize()
            m2 = np.einsum("ni,nij,nj->n", e, info, e)
            m = np.sqrt(np.maximum(m2, 0.0))
            weight = np.where((huber > 0) & (m > huber), huber / np.maximum(m, 1e-12), 1.0)
            cost = float(np.sum(np.where((huber > 0) & (m > huber), 2 * huber * m - huber**2, m2)))
            w_info = info * weight[:, None, None]
            h = np.zeros((count * 3, count * 3))
            g = np.zeros(count * 3)
            blocks = (
                (i, i, np.einsum("nki,nkl,nlj->nij", a, w_info, a)),
                (i, j, np.einsum("nki,nkl,nlj->nij", a, w_info, b)),
                (j, i, np.einsum("nki,nkl,nlj->nij", b, w_info, a)),
                (j, j, np.einsum("nki,nkl,nlj->nij", b, w_info, b)),
            )
            rows = np.arange(3)
            for r, c, blk in blocks:
                ridx = (r[:, None, None] * 3 + rows[None, :, None]) * (count * 3) + (
                    c[:, None, None] * 3 + rows[None, None, :]
                )
                np.add.at(h.reshape(-1), ridx.reshape(-1), blk.reshape(-1))
            gi = np.einsum("nki,nkl,nl->ni", a, w_info, e)
            gj = np.einsum("nki,nkl,nl->ni", b, w_info, e)
            np.add.at(g, (i[:, None] * 3 + rows[None, :]).reshape(-1), gi.reshape(-1))
            np.add.at(g, (j[:, None] * 3 + rows[None, :]).reshape(-1), gj.reshape(-1))
            f = fixed * 3
            h[f : f + 3, :] = 0.0
            h[:, f : f + 3] = 0.0
            h[f : f + 3, f : f + 3] = np.eye(3)
            g[f : f + 3] = 0.0
            step = _solve_spd(h + np.eye(count * 3) * 1e-9, -g)
            if step is None:
                break
            self.poses = self.poses + step.reshape(count, 3)
            self.poses[:, 2] = wrap(self.poses[:, 2])
            if np.abs(step).max() < 1e-6:
                break
        return cost


_BLOCK = 96
"""LAPACK (OpenBLAS) solves systems under 10 000 entries on one thread; larger ones start
threads, which on a loaded machine cost a hundred times the arithmetic."""


def _solve_spd(a: Array, b: Array) -> Array | None:
    """``a⁻¹ b`` for a symmetric positive definite ``a``, by a Cholesky factorisation over
    blocks small enough for LAPACK to stay on one thread, the products between blocks in
    ``einsum`` (numpy's own loops, never threaded). None if ``a`` is not positive definite."""
    n = len(a)
    spans = list(itertools.pairwise([*range(0, n, _BLOCK), n]))
    low: dict[tuple[int, int], Array] = {}
    inv: list[Array] = []
    try:
        for k, (k0, k1) in enumerate(spans):
            diag = a[k0:k1, k0:k1].copy()
            for j in range(k):
                diag -= np.einsum("ik,jk->ij", low[k, j], low[k, j])
            lkk = np.linalg.cholesky(diag)
            inv.append(np.linalg.inv(lkk))
            for i in range(k + 1, len(spans)):
                i0, i1 = spans[i]
                block = a[i0:i1, k0:k1].copy()
                for j in range(k):
                    block -= np.einsum("ik,jk->ij", low[i, j], low[k, j])
                low[i, k] = np.einsum("ik,jk->ij", block, inv[k])
    except np.linalg.LinAlgError:
        return None
    y: list[Array] = []
    for k, (k0, k1) in enumerate(spans):
        rhs = b[k0:k1].copy()
        for j in range(k):
            rhs -= np.einsum("ik,k->i", low[k, j], y[j])
        y.append(np.einsum("ik,k->i", inv[k], rhs))
    x: list[Array] = [np.zeros(0)] * len(spans)
    for k in range(len(spans) - 1, -1, -1):
        rhs = y[k].copy()
        for i in range(k + 1, len(spans)):
            rhs -= np.einsum("ki,k->i", low[i, k], x[i])
        x[k] = np.einsum("ki,k->i", inv[k], rhs)
    return np.concatenate(x)
