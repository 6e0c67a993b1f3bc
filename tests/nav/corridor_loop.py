"""Test data for loop closure: the mbot's laser ray-cast along a ring of corridors whose long
south side has nothing on its walls, so that scan matching cannot tell how far the robot went
there and follows the odometry; only closing the loop where the run began puts it right.

The ring is 40 m x 12 m outside, its corridors 2 m wide. The north, east and west sides
have boxes on their walls at uneven spacing (nothing repeats), the south-west corner where
the run begins has its own; the south side is bare for 30 m. The robot drives once around
counter-clockwise at 0.5 m/s and on 5 m past its start; the laser is the course's (360 beams
over ±3 rad, 0.1-6 m, 5.5 Hz) at the base's centre, with 1 cm of range noise. The odometry
drifts as :func:`tests.nav.simulated.drift` makes it.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from belvedere.graph import NS
from belvedere.msgs import message_from_data
from tests.nav import simulated
from tests.nav.raycast import cast
from tests.nav.simulated import Recording

Array = npt.NDArray[np.float64]

SPEED = 0.5
RATE = 5.5
TURN_RATE = 1.0
"""rad/s while turning on the spot at a corner."""
ANGLES = np.linspace(-3.0, 3.0, 360)
RANGE = (0.1, 6.0)
START = (2.5, 1.0)
WAYPOINTS = [(39.0, 1.0), (39.0, 11.0), (1.0, 11.0), (1.0, 1.0), (7.5, 1.0)]


def _box(cx: float, cy: float, sx: float, sy: float) -> list[list[list[float]]]:
    x0, x1, y0, y1 = cx - sx / 2, cx + sx / 2, cy - sy / 2, cy + sy / 2
    corners = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    return [[corners[i], corners[(i + 1) % 4]] for i in range(4)]


WALLS = np.array(
    _box(20.0, 6.0, 40.0, 12.0)  # the outer wall
    + _box(20.0, 6.0, 36.0, 8.0)  # the garth: corridors 2 m wide around it
    # the south-west corner, where the run begins and ends
    + _box(3.2, 0.15, 0.6, 0.3)
    + _box(4.9, 1.85, 0.3, 0.3)
    + _box(0.3, 3.4, 0.6, 0.5)
    # the west, north and east sides
    + _box(1.85, 6.3, 0.3, 0.8)
    + _box(0.2, 8.7, 0.4, 0.4)
    + _box(4.1, 11.8, 0.5, 0.4)
    + _box(9.6, 10.2, 0.4, 0.4)
    + _box(13.9, 11.75, 1.2, 0.5)
    + _box(21.3, 10.15, 0.7, 0.3)
    + _box(26.0, 11.8, 0.4, 0.4)
    + _box(31.7, 11.7, 0.9, 0.6)
    + _box(35.4, 10.2, 0.4, 0.4)
    + _box(39.8, 8.2, 0.4, 1.0)
    + _box(38.2, 5.1, 0.4, 0.6)
    + _box(39.75, 2.9, 0.5, 0.4)
)
"""Wall segments ``(S, 2, 2)``: (start, end) points in metres."""


def ranges(pose: Array, rng: np.random.Generator) -> Array:
    """One scan from ``pose`` (x, y, yaw): the distance to the nearest wall along each beam,
    with noise; ``inf`` (no return) beyond the laser's range."""
    x, y, yaw = pose
    r = cast(x, y, ANGLES + yaw, WALLS) + rng.normal(0.0, 0.01, len(ANGLES))
    return np.where((r >= RANGE[0]) & (r <= RANGE[1]), r, np.inf)


def path() -> Array:
    """The true poses at the laser's rate: straight along the corridors, turning on the
    spot at the corners."""
    step = SPEED / RATE
    turn = TURN_RATE / RATE
    poses = [(START[0], START[1], 0.0)]
    for tx, ty in WAYPOINTS:
        x, y, yaw = poses[-1]
        heading = yaw + math.remainder(math.atan2(ty - y, tx - x) - yaw, 2 * math.pi)
        while abs(heading - yaw) > 1e-9:
            yaw += max(-turn, min(turn, heading - yaw))
            poses.append((x, y, yaw))
        length = math.hypot(tx - x, ty - y)
        for k in range(1, math.ceil(length / step) + 1):
            f = min(k * step / length, 1.0)
            poses.append((x + f * (tx - x), y + f * (ty - y), yaw))
    return np.array(poses)


def record(
    seed: int = 3,
    *,
    travel: float = 0.08,
    turn: float = 0.05,
    creep: float = 1.0,
    count: int | None = None,
) -> Recording:
    """The run (its first ``count`` scans only, if given), its scans as ``sensor_msgs/LaserScan``
    messages, and drifting odometry."""
    rng = np.random.default_rng(seed)
    truth = path()[:count]
    stamps = [round((100.0 + k / RATE) * NS) for k in range(len(truth))]
    scans = [
        message_from_data(
            "sensor_msgs/LaserScan",
            {
                "header": {
                    "stamp": {"sec": ns // NS, "nanosec": ns % NS},
                    "frame_id": simulated.LASER,
                },
                "angle_min": float(ANGLES[0]),
                "angle_max": float(ANGLES[-1]),
                "angle_increment": float(ANGLES[1] - ANGLES[0]),
                "range_min": RANGE[0],
                "range_max": RANGE[1],
                "ranges": ranges(pose, rng).tolist(),
            },
        )
        for ns, pose in zip(stamps, truth, strict=True)
    ]
    odom = simulated.drift(truth, seed, travel=travel, turn=turn, creep=creep)
    return Recording(stamps, scans, truth, odom, (0.0, 0.0, 0.0))
