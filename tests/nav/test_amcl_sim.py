"""amcl on data from belvedere's physics simulation: the mbot driven once around the
cloister with drifting odometry (see ``simulated``), localized on the cloister's map and
scored against the simulation's true pose — tracking from a known start, and global
localization from particles spread over the whole map."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from belvedere.maps import OccupancyMap
from belvedere.nav.amcl import AmclParams, Localizer, laser_data
from tests.nav import simulated
from tests.nav.simulated import Recording

Floats = npt.NDArray[np.float64]


@pytest.fixture(scope="module")
def recording() -> Recording:
    return simulated.record()


@pytest.fixture(scope="module")
def grid() -> OccupancyMap:
    return simulated.world_map()


def _errors(
    rec: Recording, grid: OccupancyMap, values: dict[str, Any], *, seed: int, spread: bool = False
) -> Floats:
    """(M, 3): the scan's index, the position error (m) and the heading error (rad) of each
    estimate amcl published."""
    start = rec.truth[0]
    params = AmclParams.from_mapping(
        {
            "initial_pose_x": float(start[0]),
            "initial_pose_y": float(start[1]),
            "initial_pose_a": float(start[2]),
            **values,
        }
    )
    loc = Localizer(params, grid, seed=seed)
    if spread:
        loc.global_localization()
    laser = (rec.laser[0], rec.laser[1], 0.0)
    out = []
    for k, (scan, odom, truth) in enumerate(zip(rec.scans, rec.odom, rec.truth, strict=True)):
        data = laser_data(
            np.asarray(scan.ranges),
            scan.angle_min,
            scan.angle_increment,
            scan.range_min,
            scan.range_max,
        )
        step = loc.update(odom, data, laser)
        if step.estimate is not None:
            e = step.estimate.pose
            yaw = abs(math.remainder(e[2] - truth[2], math.tau))
            out.append((k, math.hypot(e[0] - truth[0], e[1] - truth[1]), yaw))
    return np.array(out)


def _steady(errors: Floats) -> tuple[float, float]:
    """Mean position and heading errors after the first ten estimates."""
    return float(errors[10:, 1].mean()), float(errors[10:, 2].mean())


def test_tracking_with_likelihood_field_prob(recording: Recording, grid: OccupancyMap) -> None:
    errors = _errors(recording, grid, {"laser_model_type": "likelihood_field_prob"}, seed=1)
    assert len(errors) > 60  # an estimate every resampling (every other update), all the way
    xy, yaw = _steady(errors)
    assert xy < 0.035
    assert yaw < math.radians(1.0)
    assert errors[10:, 1].max() < 0.1
    # the odometry alone ends metres off
    drift = np.hypot(*(recording.odom[-1, :2] - recording.truth[-1, :2]))
    assert drift > 0.5


def test_tracking_with_the_likelihood_field(recording: Recording, grid: OccupancyMap) -> None:
    # amcl's default model: a sum over the beams, so a flatter posterior than the product
    values = {"laser_sigma_hit": 0.1, "min_particles": 500, "max_particles": 2000}
    xy, yaw = _steady(_errors(recording, grid, values, seed=1))
    assert xy < 0.05
    assert yaw < math.radians(2.0)


def test_tracking_with_the_beam_model(recording: Recording, grid: OccupancyMap) -> None:
    values = {"laser_model_type": "beam", "min_particles": 300, "max_particles": 1000}
    xy, yaw = _steady(_errors(recording, grid, values, seed=1))
    assert xy < 0.06
    assert yaw < math.radians(2.0)


def _travel_to_convergence(rec: Recording, errors: Floats) -> float:
    """Metres driven until the estimate is within 0.2 m and 5° of the truth for good
    (infinite if it never is)."""
    lost = np.nonzero((errors[:, 1] > 0.2) | (errors[:, 2] > math.radians(5)))[0]
    if len(lost) == len(errors) or (len(lost) and lost[-1] == len(errors) - 1):
        return math.inf
    found = int(errors[lost[-1] + 1, 0]) if len(lost) else 0
    return float(np.hypot(*np.diff(rec.truth[: found + 1, :2], axis=0).T).sum())


def test_global_localization_converges_within_ten_metres(
    recording: Recording, grid: OccupancyMap
) -> None:
    values = {
        "laser_model_type": "likelihood_field_prob",
        "laser_sigma_hit": 0.5,  # a wide beam model keeps the far hypotheses alive a while
        "min_particles": 500,
        "max_particles": 5000,
        "resample_interval": 1,
    }
    travel = [
        _travel_to_convergence(recording, _errors(recording, grid, values, seed=s, spread=True))
        for s in range(1, 11)
    ]
    # most runs find the robot within a few metres; a run whose particles all settle on a
    # wrong place stays there, as amcl's does (its recovery only answers a drop in the
    # likelihood, and a filter wrong from the start never saw a better one)
    found = [t for t in travel if t < 10.0]
    assert len(found) >= 8
    assert max(found) < 6.0


def test_the_same_seed_gives_the_same_estimates(recording: Recording, grid: OccupancyMap) -> None:
    values = {"laser_model_type": "likelihood_field_prob", "max_particles": 1000}
    a = _errors(recording, grid, values, seed=4)
    b = _errors(recording, grid, values, seed=4)
    assert np.array_equal(a, b)
