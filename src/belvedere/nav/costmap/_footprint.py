"""The robot's footprint as costmap_2d reads it: a polygon or a radius, padded, and the
inscribed/circumscribed radii the inflation layer needs."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt
import yaml

__all__ = [
    "circle_footprint",
    "footprint_from_params",
    "pad_footprint",
    "radii",
]

Polygon = npt.NDArray[np.float64]

_CIRCLE_POINTS = 16
"""costmap_2d approximates a round robot by this many points on its radius."""


def circle_footprint(radius: float) -> Polygon:
    angles = np.arange(_CIRCLE_POINTS) * 2.0 * math.pi / _CIRCLE_POINTS
    return np.column_stack([np.cos(angles) * radius, np.sin(angles) * radius])


def _points(value: Any) -> Polygon:
    text = value
    if isinstance(value, str):
        try:
            text = yaml.safe_load(value)
        except yaml.YAMLError:
            text = None
    try:
        points = np.asarray(text, dtype=np.float64)
    except (TypeError, ValueError):
        points = np.empty(0)
    if points.ndim != 2 or points.shape[1] != 2 or len(points) < 3:
        message = (
            f"parameter 'footprint' must be a polygon of at least 3 [x, y] points, "
            f"like [[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]], not {value!r}"
        )
        raise ValueError(message)
    if not np.isfinite(points).all():
        message = f"parameter 'footprint' has a point that is not a finite number: {value!r}"
        raise ValueError(message)
    return points


def footprint_from_params(footprint: Any, robot_radius: Any) -> Polygon:
    """The unpadded footprint: ``footprint`` when set (a list or its string form), else a
    circle of ``robot_radius`` (costmap_2d's ``makeFootprintFromParams``)."""
    if footprint is not None and not (
        isinstance(footprint, str) and footprint.strip() in {"", "[]"}
    ):
        return _points(footprint)
    if isinstance(robot_radius, bool) or not isinstance(robot_radius, int | float):
        message = f"parameter 'robot_radius' must be a number, not {robot_radius!r}"
        raise ValueError(message)
    if robot_radius <= 0:
        message = f"parameter 'robot_radius' must be positive, not {robot_radius!r}"
        raise ValueError(message)
    return circle_footprint(float(robot_radius))


def pad_footprint(footprint: Polygon, padding: float) -> Polygon:
    """Each point moved ``padding`` outward along x and y (by the signs of its coordinates)."""
    return footprint + np.sign(footprint) * padding


def _segment_distance(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> float:
    """The distance from the origin to segment ab."""
    ab = b - a
    length_sq = float(ab @ ab)
    t = 0.0 if length_sq == 0 else float(np.clip(-(a @ ab) / length_sq, 0.0, 1.0))
    return float(np.hypot(*(a + t * ab)))


def radii(footprint: Polygon) -> tuple[float, float]:
    """(inscribed, circumscribed): the smallest and largest distance from the robot's origin
    to the footprint's vertices and edges."""
    low, high = math.inf, 0.0
    count = len(footprint)
    for k in range(count):
        a, b = footprint[k], footprint[(k + 1) % count]
        vertex = float(np.hypot(*a))
        edge = _segment_distance(a, b)
        low = min(low, vertex, edge)
        high = max(high, vertex, edge)
    return low, high
