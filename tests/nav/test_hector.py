"""hector's scan matcher on scans ray-cast in a known room: it tracks the true pose without
odometry, and its map has the walls where they are."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from belvedere.nav.slam import HectorParams, HectorSlam

Array = npt.NDArray[np.float64]


def _rectangle(x0: float, y0: float, x1: float, y1: float) -> list[list[list[float]]]:
    corners = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    return [[corners[i], corners[(i + 1) % 4]] for i in range(4)]


WALLS = np.array(
    _rectangle(-5, -4, 5, 4)  # the room
    + _rectangle(-2, -1.5, 2, 1.5)  # a block in its middle: a loop corridor around it
    + _rectangle(3.5, 2.5, 3.9, 2.9)
    + _rectangle(-4, -3, -3.6, -2.6)
)
ANGLES = np.linspace(-math.pi, math.pi, 360, endpoint=False)


def _scan(pose: tuple[float, float, float], max_range: float = 6.0) -> Array:
    """Ranges from ``pose`` to the walls (inf beyond ``max_range``)."""
    x, y, yaw = pose
    d = np.stack([np.cos(ANGLES + yaw), np.sin(ANGLES + yaw)], axis=1)
    a, e = WALLS[:, 0], WALLS[:, 1] - WALLS[:, 0]
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]
    den = np.where(den == 0, np.nan, den)
    w = a[None, :, :] - np.array([x, y])[None, None, :]
    t = (w[..., 0] * e[None, :, 1] - w[..., 1] * e[None, :, 0]) / den
    u = (w[..., 0] * d[:, None, 1] - w[..., 1] * d[:, None, 0]) / den
    t = np.where((u >= 0) & (u <= 1) & (t > 0), t, np.inf)
    r = np.nanmin(t, axis=1)
    return np.where(r < max_range, r, np.inf)


def _loop(steps: int) -> list[tuple[float, float, float]]:
    """An ellipse around the block, facing along it."""
    path = []
    for k in range(steps):
        s = k / steps * 2 * math.pi
        heading = math.atan2(2.75 * math.cos(s), -3.5 * math.sin(s))
        path.append((3.5 * math.cos(s), 2.75 * math.sin(s), heading))
    return path


def _run(seed: int) -> tuple[HectorSlam, list[float], list[float]]:
    rng = np.random.default_rng(seed)
    params = HectorParams(
        resolution=0.05, size=512, levels=3, laser_min=0.15, laser_max=6.0, angle_thresh=0.06
    )
    slam = HectorSlam(params)
    path = _loop(300)
    start = np.array(path[0])
    errors, headings = [], []
    for pose in path:
        ranges = _scan(pose) + rng.normal(0.0, 0.01, len(ANGLES))
        ok = np.isfinite(ranges) & (ranges > params.laser_min)
        points = np.column_stack((ranges[ok] * np.cos(ANGLES[ok]), ranges[ok] * np.sin(ANGLES[ok])))
        est = slam.process(points)
        # the map frame starts at the first pose: compare in the start's frame
        c, s = math.cos(start[2]), math.sin(start[2])
        dx, dy = pose[0] - start[0], pose[1] - start[1]
        truth = (c * dx + s * dy, -s * dx + c * dy, pose[2] - start[2])
        errors.append(math.hypot(est[0] - truth[0], est[1] - truth[1]))
        headings.append(abs((est[2] - truth[2] + math.pi) % (2 * math.pi) - math.pi))
    return slam, errors, headings


def test_it_tracks_a_loop_without_odometry() -> None:
    slam, errors, headings = _run(seed=1)
    assert max(errors) < 0.08  # metres, over a 20 m loop at 7 cm per scan
    assert float(np.mean(errors)) < 0.05
    assert max(headings) < math.radians(2)
    # the map: the room's far wall (x = 5 in the world) is occupied, the corridor is free
    grid = slam.map
    probability = grid.probability()
    start = _loop(300)[0]  # (3.5, 0, pi/2): the world's x = 5 wall is 1.5 m to the robot's right
    wall = grid.to_cells(np.array([[0.0, -1.5]]))[0].astype(int)
    corridor = grid.to_cells(np.array([[0.0, -0.75]]))[0].astype(int)
    assert start[0] == 3.5
    assert probability[wall[1], wall[0]] > 0.5 or probability[wall[1], wall[0] - 1] > 0.5
    assert probability[corridor[1], corridor[0]] < 0.5


def test_it_is_deterministic() -> None:
    a, errors_a, _ = _run(seed=3)
    b, errors_b, _ = _run(seed=3)
    assert errors_a == errors_b
    assert np.array_equal(a.map.cells, b.map.cells)
