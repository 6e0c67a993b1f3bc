"""Scan matching against a :class:`FieldGrid`: Gauss-Newton refinement of a pose.

The cost is ``Σ (1 - F(T(ξ)·p))²`` over the scan's end points ``p`` (``F`` the grid's field,
interpolated), plus a quadratic pull towards a predicted pose (the odometry's), weighted by its
information — the least-squares form of matching a scan to a likelihood field with a motion
prior. The Hessian at the optimum says how well constrained the match is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from belvedere.nav.slam._grid import FieldGrid, bilinear

__all__ = ["Match", "refine"]

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Match:
    pose: Array
    score: float
    """Mean field value at the end points (1 = every point on a wall's centre)."""
    hessian: Array
    """``JᵀJ`` of the field term alone (the match's information, up to a scale)."""
    cost: float = 0.0
    """``Σ (1 - F)²`` at the pose."""


def refine(
    grid: FieldGrid,
    points: Array,
    start: Array,
    prior: Array | None = None,
    prior_information: Array | None = None,
    iterations: int = 10,
) -> Match:
    """Refine ``start`` (pose of the scan's frame in the grid's frame) so that ``points``
    (N, 2), given in the scan's frame, fall on the field's ridges."""
    inv = 1.0 / grid.resolution
    # Work in cell units: u = R·p/res + (t - origin)/res - 1/2 is the point's position
    # between cell centres.
    pts = points.T * inv
    n = max(len(points), 1)
    field = grid.field.reshape(-1)
    h, w = grid.field.shape
    last = h * w - w - 1
    corner = grid.origin * inv + 0.5
    rows = np.array([1.0, float(w)])
    scale = np.array([inv, inv, 1.0])
    outer = scale[:, None] * scale[None, :]
    with_prior = prior is not None and prior_information is not None
    prior_pose = np.zeros(3) if prior is None else np.asarray(prior, dtype=np.float64)
    prior_info = np.zeros(3) if prior_information is None else prior_information
    jac = np.empty((3, len(points)))

    def evaluate(pose: Array) -> tuple[float, Array, Array, Array]:
        """Cost, field values, and the cost's JᵀJ and Jᵀr at ``pose``."""
        c, s = math.cos(pose[2]), math.sin(pose[2])
        r = np.array([[c, -s], [s, c]]) @ pts
        u = r + np.array([[pose[0] * inv - corner[0]], [pose[1] * inv - corner[1]]])
        cell = np.floor(u)
        frac = u - cell
        flat = (rows @ cell).astype(np.intp)
        if flat.min() < 0 or flat.max() >= last:
            # Cells within radius + 2 of the border never hold weight (insert pads), so a
            # point off the grid clamped onto the border reads 0 with a zero gradient.
            cell[0] = np.clip(cell[0], 0, w - 2)
            cell[1] = np.clip(cell[1], 0, h - 2)
            frac = np.clip(u - cell, 0.0, 1.0)
            flat = (rows @ cell).astype(np.intp)
        value, gx, ba = bilinear(field, w, flat, frac[0], frac[1])
        jac[0] = gx
        jac[1] = ba
        jac[2] = ba * r[0] - gx * r[1]
        residual = 1.0 - value
        cost = float(residual @ residual)
        jtj = (jac @ jac.T) * outer
        rhs = (jac @ residual) * scale
        if with_prior:
            d = pose - prior_pose
            d[2] = (d[2] + math.pi) % (2.0 * math.pi) - math.pi
            cost += float(prior_info @ (d * d))
            rhs = rhs - prior_info * d
        return cost, value, jtj, rhs

    pose = np.array(start, dtype=np.float64)
    cost, value, jtj, rhs = evaluate(pose)
    damping = 0.0
    prior_matrix = np.diag(prior_info) if with_prior else np.zeros((3, 3))
    diagonal = np.eye(3, dtype=bool)
    # Levenberg-Marquardt: the interpolated field's gradient jumps at cell boundaries, so
    # plain Gauss-Newton steps can overshoot and oscillate.
    for _ in range(max(iterations, 1)):
        hess = jtj + prior_matrix
        if damping:
            hess = hess + np.where(diagonal, hess * damping, 0.0)
        step = _solve3(hess, rhs)
        trial = pose + step
        trial[2] = (trial[2] + math.pi) % (2.0 * math.pi) - math.pi
        t_cost, t_value, t_jtj, t_rhs = evaluate(trial)
        if t_cost <= cost:
            gain = cost - t_cost
            pose, cost, value, jtj, rhs = trial, t_cost, t_value, t_jtj, t_rhs
            damping *= 0.25
            if gain <= 1e-4 * cost or (
                abs(step[0]) < 1e-3 and abs(step[1]) < 1e-3 and abs(step[2]) < 2e-4
            ):
                break
        else:
            damping = 1.0 if damping == 0.0 else damping * 4.0
            if damping > 1e3:
                break
    residual = 1.0 - value
    return Match(
        pose=pose, score=float(value.sum() / n), hessian=jtj, cost=float(residual @ residual)
    )


def _solve3(h: Array, b: Array) -> Array:
    """``h⁻¹ b`` for a symmetric 3 x 3 ``h`` (a near-singular one gives no step)."""
    a00, a01, a02 = h[0]
    a11, a12, a22 = h[1, 1], h[1, 2], h[2, 2]
    c00 = a11 * a22 - a12 * a12
    c01 = a02 * a12 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    det = a00 * c00 + a01 * c01 + a02 * c02
    if abs(det) < 1e-12:
        return np.zeros(3)
    c11 = a00 * a22 - a02 * a02
    c12 = a01 * a02 - a00 * a12
    c22 = a00 * a11 - a01 * a01
    b0, b1, b2 = b
    return np.array(
        [
            (c00 * b0 + c01 * b1 + c02 * b2) / det,
            (c01 * b0 + c11 * b1 + c12 * b2) / det,
            (c02 * b0 + c12 * b1 + c22 * b2) / det,
        ]
    )
