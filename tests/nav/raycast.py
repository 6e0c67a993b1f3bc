"""A laser ray-cast against walls, for the SLAM tests' made-up scans."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = ["cast"]

Array = npt.NDArray[np.float64]


def cast(x: float, y: float, angles: Array, walls: Array) -> Array:
    """The distance from (x, y) to the nearest wall along each beam (its heading in
    ``angles``); ``inf`` where a beam hits none. ``walls`` are segments ``(S, 2, 2)``:
    (start, end) points."""
    d = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    a, e = walls[:, 0], walls[:, 1] - walls[:, 0]
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]
    den = np.where(den == 0, np.nan, den)  # a beam along a wall: no crossing
    w = a[None, :, :] - np.array([x, y])[None, None, :]
    t = (w[..., 0] * e[None, :, 1] - w[..., 1] * e[None, :, 0]) / den
    u = (w[..., 0] * d[:, None, 1] - w[..., 1] * d[:, None, 0]) / den
    t = np.where((u >= 0) & (u <= 1) & (t > 0), t, np.inf)
    hits: Array = np.nanmin(t, axis=1)
    return hits
