"""amcl's update, ours against the PyPI package ``amcl`` (Nav2's amcl core), same run —
the beam model against the beam model — and our likelihood field beside ROS 1's figures.

The reference's compiled module has only the *beam* laser model (no likelihood field, no
``map_update_cspace``), so the ratio printed compares our beam model with its beam model, with
the same parameters. Our likelihood field model (amcl's default, what the course's launch files
use) has no reference in this run: ROS 1's own amcl core is not packaged for Debian. Its
figures on this scenario with the likelihood field (navigation noetic-devel, unmodified,
RelWithDebInfo, measured on another machine: 1.0 / 4.9 / 17.3 ms per update at 500 / 2000 /
5000 particles) are printed beside ours with their ratio, marked as not from this run.

A 20 x 20 m map at 0.05 m (outer walls, inner walls and pillars), a robot driving a circle in
it, a 360-beam laser of 10 m; each filter uses 60 beams of it, a fixed particle count (min =
max) of 500, 2000 and 5000, and updates (motion, laser, resampling) on every scan. Prints the
mean wall-clock milliseconds per update for each and the ratios.

Measured on the 2-core development machine at load ~2 (2026-11-28, two runs): beam 4.1-4.3 /
19-22 / 47-48 ms against Nav2's 5.8-6.0 / 23-24 / 62 ms (1.35-1.47x / 1.08-1.23x / 1.30x);
the likelihood field 0.34-0.36 / 0.79-0.85 / 1.66-1.70 ms (2.8-2.9x / 5.8-6.2x / 10.2-10.4x
ROS 1's figures). The code before that day's changes, interleaved with it in one process on
the same particles (bit for bit the same results), took 1.01-1.09x / 1.17x / 1.19-1.21x as
long with the likelihood field and 1.62x / 1.49x / 1.35x with the beam model (see
docs/performance.md).

    python benchmarks/amcl.py [--updates 40]
"""

from __future__ import annotations

import argparse
import importlib
import math
import sys
import time
from pathlib import Path
from types import ModuleType

import numpy as np
import numpy.typing as npt

from belvedere.maps import OccupancyMap
from belvedere.nav.amcl import AmclMap, AmclParams, LaserModel, LaserParams, Localizer, laser_data

RES = 0.05
SIZE = 400  # cells: 20 m
BEAMS = 360
RANGE_MAX = 10.0
PARTICLES = (500, 2000, 5000)
ROS1_LIKELIHOOD_FIELD_MS = {500: 1.0, 2000: 4.9, 5000: 17.3}
"""ROS 1's amcl core with the likelihood field on this scenario, measured on another machine
(see the module's description): not from this run."""


def world() -> npt.NDArray[np.int8]:
    """0 free, 100 occupied: a walled room with inner walls and pillars."""
    grid = np.zeros((SIZE, SIZE), dtype=np.int8)
    grid[:3, :] = grid[-3:, :] = grid[:, :3] = grid[:, -3:] = 100
    grid[100:103, 60:240] = 100
    grid[260:263, 160:340] = 100
    grid[150:300, 300:303] = 100
    for cx, cy in ((100, 200), (200, 120), (320, 80), (80, 320), (250, 330)):
        grid[cy - 6 : cy + 6, cx - 6 : cx + 6] = 100
    return grid


def trajectory(n: int) -> npt.NDArray[np.float64]:
    """Poses on a circle of 4 m about the map's centre, 0.25 m apart."""
    step = 0.25 / 4.0
    angles = np.arange(n) * step
    x = 10.0 + 4.0 * np.cos(angles)
    y = 10.0 + 4.0 * np.sin(angles)
    return np.stack([x, y, angles + math.pi / 2], axis=1)


def scans(grid: OccupancyMap, poses: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """(S, BEAMS) true ranges from each pose, ray cast on the map."""
    caster = LaserModel(LaserParams(model="beam", max_beams=BEAMS), AmclMap.from_occupancy(grid))
    bearings = -math.pi + np.arange(BEAMS, dtype=np.float64) * (2 * math.pi / BEAMS)
    return caster.expected_ranges(poses, (0.0, 0.0, 0.0), bearings, RANGE_MAX)


def ours(
    grid: OccupancyMap,
    odom: npt.NDArray[np.float64],
    ranges: npt.NDArray[np.float64],
    n: int,
    model: str,
) -> float:
    params = AmclParams(
        min_particles=n,
        max_particles=n,
        laser_max_beams=60,
        laser_model_type=model,
        # the reference's beam model's parameters (nav2() below), the same here
        laser_z_hit=0.95,
        laser_z_short=0.1,
        laser_z_max=0.05,
        laser_z_rand=0.05,
        laser_sigma_hit=0.2,
        laser_lambda_short=0.1,
        update_min_d=0.0,
        update_min_a=0.0,
        resample_interval=1,
        initial_pose_x=odom[0, 0],
        initial_pose_y=odom[0, 1],
        initial_pose_a=odom[0, 2],
    )
    loc = Localizer(params, grid, seed=1)
    increment = 2 * math.pi / BEAMS
    data = [laser_data(r, -math.pi, increment, 0.05, RANGE_MAX) for r in ranges]
    loc.update(odom[0], data[0], (0.0, 0.0, 0.0))
    start = time.perf_counter()
    for pose, scan in zip(odom[1:], data[1:], strict=True):
        step = loc.update(pose, scan, (0.0, 0.0, 0.0))
        assert step.resampled
    elapsed = time.perf_counter() - start
    assert loc.estimate is not None
    error = float(np.hypot(*(loc.estimate.pose[:2] - odom[-1, :2])))
    assert error < 0.3, f"ours lost the robot: {error:.2f} m off"
    return 1000.0 * elapsed / (len(odom) - 1)


def nav2(
    grid: OccupancyMap, odom: npt.NDArray[np.float64], ranges: npt.NDArray[np.float64], n: int
) -> float:
    amcl = _reference()
    motion = amcl.MotionParameters(0.2, 0.2, 0.2, 0.2, 0.2)
    laser = amcl.LaserParameters(0.95, 0.1, 0.05, 0.05, 0.2, 0.1, 0.05, 60)
    filt = amcl.AMCL(n, n, 0.001, 0.1, motion, laser, "differential")
    cells = grid.data.astype(int).tolist()
    filt.set_map(amcl.create_occupancy_grid_from_list(cells, RES, 0.0, 0.0))
    filt.set_laser_pose(amcl.Vector3D(0.0, 0.0, 0.0))
    filt.set_initial_pose(
        amcl.Vector3D(*odom[0]), amcl.create_diagonal_covariance(0.25, 0.25, 0.07)
    )
    bearings = -math.pi + np.arange(BEAMS) * (2 * math.pi / BEAMS)
    scans_ = [
        amcl.create_laser_scan_from_list(np.stack([r, bearings], axis=1).tolist(), RANGE_MAX)
        for r in ranges
    ]
    filt.update(scans_[0], amcl.Vector3D(*odom[0]))
    start = time.perf_counter()
    for pose, scan in zip(odom[1:], scans_[1:], strict=True):
        filt.update(scan, amcl.Vector3D(*pose))
    elapsed = time.perf_counter() - start
    return 1000.0 * elapsed / (len(odom) - 1)


def _reference() -> ModuleType:
    """The PyPI package ``amcl``, which this script's own name would shadow."""
    here = Path(__file__).resolve().parent
    sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != here]
    sys.modules.pop("amcl", None)
    return importlib.import_module("amcl")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--updates", type=int, default=40)
    args = parser.parse_args()
    grid = OccupancyMap(world(), RES)
    truth = trajectory(args.updates + 1)
    ranges = scans(grid, truth)
    print(
        f"{'particles':>9} {'ours beam':>10} {'nav2 beam':>10} {'ratio':>7}"
        f"   {'ours lf':>9} {'ROS 1 lf*':>10} {'ratio*':>7}"
    )
    for n in PARTICLES:
        a = ours(grid, truth, ranges, n, "beam")
        b = nav2(grid, truth, ranges, n)
        c = ours(grid, truth, ranges, n, "likelihood_field")
        ros1 = ROS1_LIKELIHOOD_FIELD_MS[n]
        print(
            f"{n:>9} {a:>8.2f}ms {b:>8.2f}ms {b / a:>6.2f}x"
            f"   {c:>7.2f}ms {ros1:>8.1f}ms {ros1 / c:>6.1f}x"
        )
    print("* ROS 1's amcl core measured on another machine, not in this run")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
