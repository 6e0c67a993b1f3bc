"""ROS 1's ``tf.transformations``: 4x4 homogeneous matrices, Euler angles in all 24 axis
conventions, and quaternions stored ``[x, y, z, w]`` (the order of ROS messages; the module
tf shipped predates the ``[w, x, y, z]`` order of its upstream's later releases).

Written for belvedere from the mathematics (Shoemake's Euler-angle parametrisation, Shepperd's
matrix-to-quaternion method, Kabsch's superimposition, Thomas's matrix decomposition); the
results, branch choices near singularities, return types and error messages follow the module
tf ships, and are checked against it (tests/ros1/test_transformations.py).

Axis conventions are a string ``'sxyz'`` … ``'rzyx'`` — ``s`` for static (fixed) axes, ``r``
for rotating ones, then the three axes in the order the rotations are applied — or tf's
encoded tuple ``(first axis, parity, repetition, frame)``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Final

import numpy as np
import numpy.typing as npt

__all__ = [
    "compose_matrix",
    "concatenate_matrices",
    "decompose_matrix",
    "euler_from_matrix",
    "euler_from_quaternion",
    "euler_matrix",
    "identity_matrix",
    "inverse_matrix",
    "is_same_transform",
    "quaternion_about_axis",
    "quaternion_conjugate",
    "quaternion_from_euler",
    "quaternion_from_matrix",
    "quaternion_inverse",
    "quaternion_matrix",
    "quaternion_multiply",
    "quaternion_slerp",
    "random_quaternion",
    "random_rotation_matrix",
    "random_vector",
    "reflection_matrix",
    "rotation_from_matrix",
    "rotation_matrix",
    "scale_matrix",
    "superimposition_matrix",
    "translation_from_matrix",
    "translation_matrix",
    "unit_vector",
    "vector_norm",
]

Array = npt.NDArray[np.float64]
Vector = Sequence[float] | npt.NDArray[Any]
"""A vector argument: tf slices it (``v[:3]``) before anything else, as tf does."""

# Below this, a length or a cosine counts as zero (tf's threshold: four machine epsilons).
_EPS: Final = float(np.finfo(float).eps) * 4.0

_AXIS_INDEX: Final = {"x": 0, "y": 1, "z": 2}
_NEXT_AXIS: Final = [1, 2, 0, 1]  # tf's table (some scripts read it): the axis after each


def _axes_table() -> dict[str, tuple[int, int, int, int]]:
    """tf's encoding of each convention: a rotating-axes sequence ``rabc`` is the static one
    ``scba`` with the first and last angles swapped, so both reduce to a static sequence
    described by its first axis, whether the second axis is the cyclic successor of the first
    (parity 0) or not, and whether the first axis comes back as the third (repetition)."""
    table: dict[str, tuple[int, int, int, int]] = {}
    for frame, kind in enumerate("sr"):
        for a in "xyz":
            for b in "xyz":
                for c in "xyz":
                    if a == b or b == c:
                        continue
                    first, second, third = (a, b, c) if kind == "s" else (c, b, a)
                    i, j = _AXIS_INDEX[first], _AXIS_INDEX[second]
                    parity = 0 if j == (i + 1) % 3 else 1
                    table[f"{kind}{a}{b}{c}"] = (i, parity, int(first == third), frame)
    return table


_AXES2TUPLE: Final = _axes_table()
_TUPLE2AXES: Final = {v: k for k, v in _AXES2TUPLE.items()}


def _convention(axes: Any, *, fold_case: bool) -> tuple[int, int, int, int]:
    """The encoded tuple of ``axes``; unknown conventions raise ``KeyError`` as tf does."""
    if isinstance(axes, str):
        key = axes.lower() if fold_case else axes
        if key in _AXES2TUPLE:
            return _AXES2TUPLE[key]
    _TUPLE2AXES[axes]  # raises KeyError (or TypeError when unhashable) for anything else
    first, parity, repetition, frame = axes
    return int(first), int(parity), int(repetition), int(frame)


def _ijk(first: int, parity: int) -> tuple[int, int, int]:
    """The three axis indices of a static sequence: ``i`` first, ``j`` second, ``k`` the
    remaining one (the third rotation's axis unless the sequence repeats ``i``)."""
    if parity:
        return first, (first + 2) % 3, (first + 1) % 3
    return first, (first + 1) % 3, (first + 2) % 3


# --- matrices ------------------------------------------------------------------------------


def identity_matrix() -> Array:
    """The 4x4 identity."""
    return np.identity(4, dtype=np.float64)


def translation_matrix(direction: npt.ArrayLike) -> Array:
    """A pure translation by ``direction`` (its first three values)."""
    m = np.identity(4)
    m[:3, 3] = np.asarray(direction)[:3]
    return m


def translation_from_matrix(matrix: npt.ArrayLike) -> Any:
    """The translation part (a new array) of a homogeneous matrix."""
    return np.asarray(matrix)[:3, 3].copy()


def inverse_matrix(matrix: npt.ArrayLike) -> Array:
    """The inverse of a square matrix."""
    return np.linalg.inv(np.asarray(matrix, dtype=np.float64))


def concatenate_matrices(*matrices: npt.ArrayLike) -> Array:
    """The product of the matrices, left to right (the identity for none)."""
    result = np.identity(4)
    for m in matrices:
        result = np.dot(result, m)
    return result


def is_same_transform(matrix0: npt.ArrayLike, matrix1: npt.ArrayLike) -> bool:
    """Whether two homogeneous matrices transform alike (after dividing by their ``[3, 3]``)."""
    a = np.array(matrix0, dtype=np.float64)
    b = np.array(matrix1, dtype=np.float64)
    return bool(np.allclose(a / a[3, 3], b / b[3, 3]))


def _skew(v: Array) -> Array:
    """The matrix of ``w -> v x w``."""
    return np.array(((0.0, -v[2], v[1]), (v[2], 0.0, -v[0]), (-v[1], v[0], 0.0)))


def rotation_matrix(
    angle: float, direction: npt.ArrayLike, point: npt.ArrayLike | None = None
) -> Array:
    """A rotation by ``angle`` (radians, right-handed) about the axis along ``direction``
    through ``point`` (the origin by default)."""
    u = unit_vector(np.asarray(direction)[:3])
    c, s = math.cos(angle), math.sin(angle)
    # Rodrigues: cos·I + (1 - cos)·u uᵀ + sin·skew(u)
    r = np.diag([c, c, c]) + np.outer(u, u) * (1.0 - c) + _skew(u * s)
    m = np.identity(4)
    m[:3, :3] = r
    if point is not None:
        p = np.asarray(point, dtype=np.float64)[:3]
        m[:3, 3] = p - np.dot(r, p)
    return m


def rotation_from_matrix(matrix: npt.ArrayLike) -> tuple[float, Array, Array]:
    """``(angle, direction, point)`` of a rotation matrix: ``direction`` a unit vector along
    the axis, ``point`` (homogeneous, ``w`` 1) the point of the axis nearest the origin."""
    m = np.array(matrix, dtype=np.float64)
    r = m[:3, :3]
    values, vectors = np.linalg.eig(r.T)
    ones = np.flatnonzero(np.abs(np.real(values) - 1.0) < 1e-8)
    if not len(ones):
        msg = "no unit eigenvector corresponding to eigenvalue 1"
        raise ValueError(msg)
    direction = np.real(vectors[:, ones[-1]]).copy()
    direction /= math.sqrt(float(np.dot(direction, direction)))
    cosa = (float(np.trace(r)) - 1.0) / 2.0
    # The antisymmetric part of R is sin(angle)·skew(direction).
    axial = np.array((r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]))
    sina = float(np.dot(axial, direction)) / 2.0
    # Points x on the axis solve (I - R) x = t; the least-squares solution of least norm is
    # the one nearest the origin.
    on_axis = np.linalg.lstsq(np.identity(3) - r, m[:3, 3], rcond=None)[0]
    point = np.append(on_axis, 1.0)
    return math.atan2(sina, cosa), direction, point


def scale_matrix(
    factor: float, origin: npt.ArrayLike | None = None, direction: npt.ArrayLike | None = None
) -> Array:
    """Scaling by ``factor`` about ``origin``: uniform, or only along ``direction``."""
    if direction is None:
        m = np.diag([factor, factor, factor, 1.0]).astype(np.float64)
        if origin is not None:
            m[:3, 3] = np.asarray(origin)[:3]
            m[:3, 3] *= 1.0 - factor
        return m
    u = unit_vector(np.asarray(direction)[:3])
    shrink = 1.0 - factor
    m = np.identity(4)
    m[:3, :3] -= shrink * np.outer(u, u)
    if origin is not None:
        m[:3, 3] = (shrink * np.dot(np.asarray(origin)[:3], u)) * u
    return m


def reflection_matrix(point: npt.ArrayLike, normal: npt.ArrayLike) -> Array:
    """A mirroring at the plane through ``point`` with normal ``normal``."""
    n = unit_vector(np.asarray(normal)[:3])
    m = np.identity(4)
    m[:3, :3] -= 2.0 * np.outer(n, n)
    m[:3, 3] = (2.0 * np.dot(np.asarray(point)[:3], n)) * n
    return m


# --- Euler angles --------------------------------------------------------------------------


def _elementary(axis: int, angle: float) -> Array:
    """The 3x3 rotation by ``angle`` about coordinate axis ``axis``."""
    c, s = math.cos(angle), math.sin(angle)
    j, k = (axis + 1) % 3, (axis + 2) % 3
    r = np.zeros((3, 3))
    r[axis, axis] = 1.0
    r[j, j] = r[k, k] = c
    r[k, j] = s
    r[j, k] = -s
    return r


def euler_matrix(ai: float, aj: float, ak: float, axes: Any = "sxyz") -> Array:
    """The rotation of Euler angles ``ai, aj, ak`` in convention ``axes`` (exact names only,
    as tf's ``euler_matrix`` takes them)."""
    first, parity, repetition, frame = _convention(axes, fold_case=False)
    if frame:
        ai, ak = ak, ai
    i, j, k = _ijk(first, parity)
    third = i if repetition else k
    # A static sequence applies the first angle first: R = R_third(ak) R_j(aj) R_i(ai).
    r = _elementary(third, ak) @ _elementary(j, aj) @ _elementary(i, ai)
    m = np.identity(4)
    m[:3, :3] = r
    return m


def euler_from_matrix(matrix: npt.ArrayLike, axes: Any = "sxyz") -> tuple[float, float, float]:
    """Euler angles of the rotation part of ``matrix`` in convention ``axes``; in gimbal lock
    the third angle is 0."""
    first, parity, repetition, frame = _convention(axes, fold_case=True)
    i, j, k = _ijk(first, parity)
    m = np.asarray(matrix, dtype=np.float64)[:3, :3]
    # An odd axis order is the even one seen in a mirror: the even formulas on the permuted
    # entries give the negated angles (Shoemake's parametrisation).
    if repetition:
        sy = math.sqrt(float(m[i, j]) ** 2 + float(m[i, k]) ** 2)
        if sy > _EPS:
            ax = math.atan2(float(m[i, j]), float(m[i, k]))
            ay = math.atan2(sy, float(m[i, i]))
            az = math.atan2(float(m[j, i]), -float(m[k, i]))
        else:
            ax = math.atan2(-float(m[j, k]), float(m[j, j]))
            ay = math.atan2(sy, float(m[i, i]))
            az = 0.0
    else:
        cy = math.sqrt(float(m[i, i]) ** 2 + float(m[j, i]) ** 2)
        if cy > _EPS:
            ax = math.atan2(float(m[k, j]), float(m[k, k]))
            ay = math.atan2(-float(m[k, i]), cy)
            az = math.atan2(float(m[j, i]), float(m[i, i]))
        else:
            ax = math.atan2(-float(m[j, k]), float(m[j, j]))
            ay = math.atan2(-float(m[k, i]), cy)
            az = 0.0
    if parity:
        ax, ay, az = -ax, -ay, -az
    if frame:
        ax, az = az, ax
    return ax, ay, az


def euler_from_quaternion(quaternion: Vector, axes: Any = "sxyz") -> tuple[float, float, float]:
    """Euler angles of an ``[x, y, z, w]`` quaternion in convention ``axes``."""
    return euler_from_matrix(quaternion_matrix(quaternion), axes)


def quaternion_from_euler(ai: float, aj: float, ak: float, axes: Any = "sxyz") -> Array:
    """The ``[x, y, z, w]`` quaternion of Euler angles in convention ``axes``."""
    first, parity, repetition, frame = _convention(axes, fold_case=True)
    if frame:
        ai, ak = ak, ai
    i, j, k = _ijk(first, parity)
    third = i if repetition else k
    q = quaternion_multiply(
        quaternion_multiply(_axis_quaternion(third, ak), _axis_quaternion(j, aj)),
        _axis_quaternion(i, ai),
    )
    return q


def _axis_quaternion(axis: int, angle: float) -> Array:
    q = np.zeros(4)
    q[axis] = math.sin(angle / 2.0)
    q[3] = math.cos(angle / 2.0)
    return q


# --- quaternions ---------------------------------------------------------------------------


def quaternion_about_axis(angle: float, axis: npt.ArrayLike) -> Array:
    """The quaternion of a rotation by ``angle`` about ``axis`` (normalised unless ~zero)."""
    q = np.zeros(4)
    q[:3] = np.asarray(axis)[:3]
    length = vector_norm(q)
    if length > _EPS:
        q *= math.sin(angle / 2.0) / length
    q[3] = math.cos(angle / 2.0)
    return q


def quaternion_matrix(quaternion: Vector) -> Array:
    """The rotation matrix of a quaternion (normalised first; ~zero gives the identity)."""
    q = np.array(quaternion[:4], dtype=np.float64)
    n = float(np.dot(q, q))
    if n < _EPS:
        return np.identity(4)
    # With q scaled to length sqrt(2), each entry is one product (or 1 minus two of them).
    x, y, z, w = (float(c) for c in q * math.sqrt(2.0 / n))
    return np.array(
        (
            (1.0 - y * y - z * z, x * y - z * w, x * z + y * w, 0.0),
            (x * y + z * w, 1.0 - x * x - z * z, y * z - x * w, 0.0),
            (x * z - y * w, y * z + x * w, 1.0 - x * x - y * y, 0.0),
            (0.0, 0.0, 0.0, 1.0),
        )
    )


def quaternion_from_matrix(matrix: npt.ArrayLike) -> Array:
    """The quaternion of the rotation part of a homogeneous matrix (Shepperd's method: the
    largest of ``w, x, y, z`` is found first, and comes out positive)."""
    m = np.asarray(matrix, dtype=np.float64)[:4, :4]
    h = float(m[3, 3])
    q = np.empty(4)
    trace4 = float(np.trace(m))
    if trace4 > h:
        q[:] = (m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1], trace4)
        t = trace4
    else:
        i = int(np.argmax(np.diag(m)[:3]))  # the first largest on ties
        j, k = (i + 1) % 3, (i + 2) % 3
        t = float(m[i, i]) - (float(m[j, j]) + float(m[k, k])) + h
        q[i] = t
        q[j] = m[i, j] + m[j, i]
        q[k] = m[k, i] + m[i, k]
        q[3] = m[k, j] - m[j, k]
    q *= 0.5 / math.sqrt(t * h)
    return q


def quaternion_multiply(quaternion1: npt.ArrayLike, quaternion0: npt.ArrayLike) -> Array:
    """The Hamilton product ``quaternion1 * quaternion0`` (rotate by ``quaternion0`` first)."""
    x0, y0, z0, w0 = (float(c) for c in np.asarray(quaternion0, dtype=np.float64))
    x1, y1, z1, w1 = (float(c) for c in np.asarray(quaternion1, dtype=np.float64))
    return np.array(
        (
            w1 * x0 + x1 * w0 + y1 * z0 - z1 * y0,
            w1 * y0 - x1 * z0 + y1 * w0 + z1 * x0,
            w1 * z0 + x1 * y0 - y1 * x0 + z1 * w0,
            w1 * w0 - x1 * x0 - y1 * y0 - z1 * z0,
        )
    )


def quaternion_conjugate(quaternion: Sequence[float] | Array) -> Array:
    """``[-x, -y, -z, w]``."""
    return np.array((-quaternion[0], -quaternion[1], -quaternion[2], quaternion[3]), np.float64)


def quaternion_inverse(quaternion: Sequence[float] | Array) -> Array:
    """The conjugate divided by the squared norm."""
    q = np.asarray(quaternion, dtype=np.float64)
    inverse: Array = quaternion_conjugate(quaternion) / np.dot(q, q)
    return inverse


def quaternion_slerp(
    quat0: npt.ArrayLike,
    quat1: npt.ArrayLike,
    fraction: float,
    spin: int = 0,
    shortestpath: bool = True,
) -> Array:
    """Spherical linear interpolation from ``quat0`` (fraction 0) to ``quat1`` (1), with
    ``spin`` extra half turns, the short way round unless ``shortestpath`` is false."""
    q0: Array = unit_vector(np.asarray(quat0)[:4])
    q1: Array = unit_vector(np.asarray(quat1)[:4])
    if fraction == 0.0:
        return q0
    if fraction == 1.0:
        return q1
    d = float(np.dot(q0, q1))
    if abs(abs(d) - 1.0) < _EPS:
        return q0
    if shortestpath and d < 0.0:
        d, q1 = -d, -q1
    angle = math.acos(d) + spin * math.pi
    if abs(angle) < _EPS:
        return q0
    s = math.sin(angle)
    result: Array = (math.sin((1.0 - fraction) * angle) / s) * q0 + (
        math.sin(fraction * angle) / s
    ) * q1
    return result


def random_quaternion(rand: Sequence[float] | Array | None = None) -> Array:
    """A uniformly distributed unit quaternion; ``rand``: three numbers in [0, 1) to make it
    from (Shoemake's subgroup algorithm), random ones by default."""
    u = np.random.rand(3) if rand is None else np.asarray(rand, dtype=np.float64)
    if u.shape != (3,):
        msg = f"random_quaternion: rand must hold three numbers, not {len(u)}"
        raise ValueError(msg)
    r1, r2 = math.sqrt(1.0 - u[0]), math.sqrt(u[0])
    t1, t2 = 2.0 * math.pi * u[1], 2.0 * math.pi * u[2]
    return np.array((math.sin(t1) * r1, math.cos(t1) * r1, math.sin(t2) * r2, math.cos(t2) * r2))


def random_rotation_matrix(rand: Sequence[float] | Array | None = None) -> Array:
    """A uniformly distributed rotation (see :func:`random_quaternion`)."""
    return quaternion_matrix(random_quaternion(rand))


def random_vector(size: int | tuple[int, ...]) -> Array:
    """Random numbers in [0, 1)."""
    return np.random.random(size)


# --- vectors -------------------------------------------------------------------------------


def vector_norm(data: npt.ArrayLike, axis: int | None = None, out: Array | None = None) -> Any:
    """The Euclidean length of ``data`` (a float for a vector), or of its slices along
    ``axis``; with ``out``, written there and ``None`` returned."""
    a = np.array(data, dtype=np.float64)
    if out is not None:
        np.sum(a * a, axis=axis, out=out)
        np.sqrt(out, out)
        return None
    if a.ndim == 1:
        return math.sqrt(float(np.dot(a, a)))
    return np.atleast_1d(np.sqrt(np.sum(a * a, axis=axis)))


def unit_vector(data: npt.ArrayLike, axis: int | None = None, out: Array | None = None) -> Any:
    """``data`` divided by its length (along ``axis``); with ``out``, written there and
    ``None`` returned."""
    if out is None:
        a = np.array(data, dtype=np.float64)
        if a.ndim == 1:
            a /= math.sqrt(float(np.dot(a, a)))
            return a
    else:
        if out is not data:
            out[:] = np.asarray(data)
        a = out
    length = np.atleast_1d(np.sqrt(np.sum(a * a, axis)))
    if axis is not None:
        length = np.expand_dims(length, axis)
    a /= length
    return a if out is None else None


# --- decomposition -------------------------------------------------------------------------


def compose_matrix(
    scale: npt.ArrayLike | None = None,
    shear: npt.ArrayLike | None = None,
    angles: npt.ArrayLike | None = None,
    translate: npt.ArrayLike | None = None,
    perspective: npt.ArrayLike | None = None,
) -> Array:
    """The matrix ``perspective · translate · rotate(sxyz angles) · shear · scale``; the
    inverse of :func:`decompose_matrix`. Shear: x-y, x-z, y-z factors."""
    m = np.identity(4)
    if perspective is not None:
        p = np.identity(4)
        p[3, :] = np.asarray(perspective)[:4]
        m = m @ p
    if translate is not None:
        m = m @ translation_matrix(translate)
    if angles is not None:
        a = np.asarray(angles)
        m = m @ euler_matrix(a[0], a[1], a[2], "sxyz")
    if shear is not None:
        sh = np.asarray(shear)
        z = np.identity(4)
        z[0, 1], z[0, 2], z[1, 2] = sh[0], sh[1], sh[2]
        m = m @ z
    if scale is not None:
        sc = np.asarray(scale)
        m = m @ np.diag([sc[0], sc[1], sc[2], 1.0])
    m /= m[3, 3]
    return m


def decompose_matrix(
    matrix: npt.ArrayLike,
) -> tuple[Array, list[float], list[float], Array, Array]:
    """``(scale, shear, angles, translate, perspective)`` of a non-degenerate homogeneous
    matrix (Thomas's "Decomposing a matrix into simple transformations", Graphics Gems II):
    angles about static x, y, z; shear x-y, x-z, y-z; a negative determinant negates the
    scale."""
    m = np.array(matrix, dtype=np.float64).T  # rows of m are the columns of the matrix
    if abs(m[3, 3]) < _EPS:
        msg = "M[3, 3] is zero"
        raise ValueError(msg)
    m /= m[3, 3]
    p = m.copy()
    p[:, 3] = 0.0, 0.0, 0.0, 1.0
    if not np.linalg.det(p):
        msg = "Matrix is singular"
        raise ValueError(msg)
    if np.any(np.abs(m[:3, 3]) > _EPS):
        perspective = np.dot(m[:, 3], np.linalg.inv(p.T))
        m[:, 3] = 0.0, 0.0, 0.0, 1.0
    else:
        perspective = np.array((0.0, 0.0, 0.0, 1.0))
    translate = m[3, :3].copy()
    # Gram-Schmidt over the three axes gives the scales and the shears.
    col = m[:3, :3].copy()
    scale = np.zeros(3)
    scale[0] = vector_norm(col[0])
    col[0] /= scale[0]
    xy = float(np.dot(col[0], col[1]))
    col[1] -= col[0] * xy
    scale[1] = vector_norm(col[1])
    col[1] /= scale[1]
    xy /= float(scale[1])
    xz = float(np.dot(col[0], col[2]))
    col[2] -= col[0] * xz
    yz = float(np.dot(col[1], col[2]))
    col[2] -= col[1] * yz
    scale[2] = vector_norm(col[2])
    col[2] /= scale[2]
    shear = [xy, xz / float(scale[2]), yz / float(scale[2])]
    if np.dot(col[0], np.cross(col[1], col[2])) < 0:
        scale *= -1
        col *= -1
    # col[c, r] is entry (r, c) of the rotation R = Rz Ry Rx.
    pitch = math.asin(-float(col[0, 2]))
    if math.cos(pitch):
        roll = math.atan2(float(col[1, 2]), float(col[2, 2]))
        yaw = math.atan2(float(col[0, 1]), float(col[0, 0]))
    else:
        roll = math.atan2(-float(col[2, 1]), float(col[1, 1]))
        yaw = 0.0
    return scale, shear, [roll, pitch, yaw], translate, perspective


def superimposition_matrix(
    v0: npt.ArrayLike, v1: npt.ArrayLike, scaling: bool = False, usesvd: bool = True
) -> Array:
    """The rigid transform (with uniform scaling if ``scaling``) that best maps the points
    ``v0`` onto ``v1`` (shape (3, n) or (4, n), n >= 3) in the least-squares sense (Kabsch's
    method; ``usesvd`` is accepted for tf's signature, the solution being the same)."""
    del usesvd
    a = np.array(v0, dtype=np.float64)[:3]
    b = np.array(v1, dtype=np.float64)[:3]
    if a.shape != b.shape or a.ndim != 2 or a.shape[1] < 3:
        msg = "Vector sets are of wrong shape or type."
        raise ValueError(msg)
    ca, cb = a.mean(axis=1), b.mean(axis=1)
    a = a - ca[:, None]
    b = b - cb[:, None]
    u, _, vh = np.linalg.svd(b @ a.T)
    r = u @ vh
    if np.linalg.det(r) < 0.0:
        # the best proper rotation flips the least significant direction
        r -= np.outer(u[:, 2], vh[2, :] * 2.0)
    m = np.identity(4)
    m[:3, :3] = r
    if scaling:
        m[:3, :3] *= math.sqrt(float(np.sum(b * b)) / float(np.sum(a * a)))
    m[:3, 3] = cb - m[:3, :3] @ ca
    return m
