"""amcl's faster paths give what the plain ones give: the likelihood fields' wide off-map
border (only particle positions clipped) against the one-cell border with every beam end
clipped, the beam model's march against a fine walk along each ray, the heading wrap against
its formula, convergence from the extremes, and resampling with the headings handed in."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from belvedere.maps import OccupancyMap
from belvedere.nav.amcl import AmclMap, LaserData, LaserModel, LaserParams, ParticleFilter, _laser
from belvedere.nav.amcl._map import FREE
from belvedere.nav.amcl._motion import _wrap

Floats = npt.NDArray[np.float64]


def _hall() -> AmclMap:
    """8 x 6 m at 0.05 m: outer walls, two pillars, an unknown patch, from (-1, -2)."""
    data = np.zeros((120, 160), dtype=np.int8)
    data[:2, :] = data[-2:, :] = data[:, :2] = data[:, -2:] = 100
    data[40:50, 60:70] = 100
    data[80:84, 100:130] = 100
    data[10:20, 10:20] = -1
    return AmclMap.from_occupancy(OccupancyMap(data, 0.05, origin=(-1.0, -2.0, 0.0)))


def _poses(rng: np.random.Generator, n: int) -> Floats:
    """Particles on the map, about its edges, and far off it."""
    near = np.column_stack([rng.uniform(-4.0, 10.0, n), rng.uniform(-6.0, 7.0, n)])
    far = np.column_stack([rng.uniform(-60.0, 60.0, n), rng.uniform(-60.0, 60.0, n)])
    xy = np.vstack([near, far])
    return np.column_stack([xy, rng.uniform(-math.pi, math.pi, 2 * n)])


def _scan(rng: np.random.Generator, range_max: float) -> LaserData:
    ranges = rng.uniform(0.05, range_max, 90)
    ranges[::9] = range_max
    bearings = np.linspace(-math.pi, math.pi, 90, endpoint=False)
    return LaserData(ranges, bearings, range_max)


@pytest.mark.parametrize("model", ["likelihood_field", "likelihood_field_prob"])
def test_the_wide_border_weighs_as_clipping_every_beam_end(
    model: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(5)
    amcl_map = _hall()
    poses = _poses(rng, 3000)
    params = LaserParams(model=model, max_beams=90, do_beamskip=True, beam_skip_threshold=0.05)
    for range_max in (3.5, 12.0):
        data = _scan(rng, range_max)
        wide = LaserModel(params, amcl_map)
        assert wide._pad(range_max) > 1
        wide_factors = wide.weigh(poses, (0.1, -0.05, 0.3), data, converged=True)
        with monkeypatch.context() as patch:
            patch.setattr(_laser, "_WIDE_TABLE", 1)  # every wide table too large
            narrow = LaserModel(params, amcl_map)
            assert narrow._pad(range_max) == 1
            narrow_factors = narrow.weigh(poses, (0.1, -0.05, 0.3), data, converged=True)
            narrow_skipped = narrow.skipped_beams
            narrow_off = narrow.weigh(np.array([[-50.0, -50.0, 0.0]]), (0.0, 0.0, 0.0), data)
        assert np.array_equal(wide_factors, narrow_factors)
        assert wide.skipped_beams == narrow_skipped
        # far off the map every beam ends off it: the off-map value for every beam
        off = wide.weigh(np.array([[500.0, -700.0, 1.0]]), (0.0, 0.0, 0.0), data)
        assert off[0] == narrow_off[0]


def _walk(amcl_map: AmclMap, pose: Floats, bearing: float, range_max: float) -> float:
    """Metres to the first cell that is not free (or the map's edge), by 1 mm steps."""
    heading = pose[2] + bearing
    r = np.arange(int(range_max * 1000) + 1) / 1000.0
    col, row = amcl_map.cell_of(pose[0] + r * math.cos(heading), pose[1] + r * math.sin(heading))
    inside = (col >= 0) & (col < amcl_map.width) & (row >= 0) & (row < amcl_map.height)
    stops = ~inside
    stops[inside] = amcl_map.states[row[inside], col[inside]] != FREE
    first = np.flatnonzero(stops)
    return float(r[first[0]]) if len(first) else range_max


def test_the_beam_march_stops_in_the_first_cell_a_fine_walk_stops_in() -> None:
    rng = np.random.default_rng(8)
    amcl_map = _hall()
    free = amcl_map.free_cells()
    # anywhere, and next to the outer walls (rays from there must stop at them, not leave)
    edge = free[(free.min(axis=1) <= 3) | (free[:, 0] >= amcl_map.width - 4)]
    cells = np.vstack([free[rng.integers(0, len(free), 40)], edge[rng.integers(0, len(edge), 40)]])
    poses = np.column_stack(
        [
            amcl_map.origin_x + (cells[:, 0] + rng.random(80)) * 0.05,
            amcl_map.origin_y + (cells[:, 1] + rng.random(80)) * 0.05,
            rng.uniform(-math.pi, math.pi, 80),
        ]
    )
    bearings = np.linspace(-math.pi, math.pi, 24, endpoint=False)
    model = LaserModel(LaserParams(model="beam"), amcl_map)
    expected = model.expected_ranges(poses, (0.0, 0.0, 0.0), bearings, 5.0)
    walked = np.array(
        [[_walk(amcl_map, pose, bearing, 5.0) for bearing in bearings] for pose in poses]
    )
    # the march never stops short of the first stop, and stops in it or in a cell touching
    # it, except where a ray only grazes a stop cell's corner: half-cell steps may pass it
    assert (expected >= walked - 0.05 * math.sqrt(2.0)).all()
    agree = np.abs(expected - walked) <= 0.05 * math.sqrt(2.0)
    assert agree.mean() > 0.97
    assert (expected[walked == 5.0] == 5.0).all()
    # off the map, every ray stops where it starts
    off = model.expected_ranges(np.array([[-5.0, 0.0, 0.0]]), (0.0, 0.0, 0.0), bearings, 5.0)
    assert (off == 0.0).all()


def test_the_heading_wrap_is_the_formula_bit_for_bit() -> None:
    rng = np.random.default_rng(2)
    with np.errstate(invalid="ignore"):
        for scale in (1.0, math.pi, 10.0, 1e6):
            angles = rng.uniform(-scale, scale, 10_000)
            angles[:6] = [math.pi, -math.pi, 0.0, -0.0, math.nextafter(math.pi, 0.0), np.nan]
            wrapped = _wrap(angles.copy())
            formula = (angles + np.pi) % (2.0 * np.pi) - np.pi
            assert np.array_equal(wrapped, formula, equal_nan=True)
            assert ((wrapped >= -np.pi) & (wrapped < np.pi))[6:].all()


def _filter(rng: np.random.Generator) -> ParticleFilter:
    amcl_map = _hall()
    return ParticleFilter(
        100,
        2000,
        alpha_slow=0.001,
        alpha_fast=0.1,
        random_poses=amcl_map.random_poses,
        rng=rng,
    )


def test_convergence_is_every_particle_within_half_a_metre_of_the_mean() -> None:
    pf = _filter(np.random.default_rng(0))
    pf.poses = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.25, 0.0]])
    pf._update_converged()
    assert pf.converged  # 0.5 from the mean in x, exactly at the limit
    pf.poses = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 1.5, 0.0]])
    pf._update_converged()
    assert not pf.converged  # 1 m from the mean in y
    pf.poses = np.array([[0.0, 0.0, 0.0], [np.nan, 0.0, 0.0]])
    pf._update_converged()
    assert not pf.converged


def test_resampling_with_the_headings_handed_in_is_resampling_without() -> None:
    results = []
    for hand_in in (False, True):
        rng = np.random.default_rng(11)
        pf = _filter(rng)
        pf.init_gaussian([2.0, 1.0, 0.5], np.diag([0.3, 0.3, 0.2]))
        for k in range(6):
            weights = np.exp(-np.hypot(pf.poses[:, 0] - 2.5, pf.poses[:, 1] - 1.0))
            # a drop in the likelihood at the fourth update: random particles are injected
            pf.update_sensor(weights * (0.01 if k == 3 else 1.0))
            poses = pf.poses
            headings = (np.cos(poses[:, 2]), np.sin(poses[:, 2])) if hand_in else None
            pf.resample(headings)
        results.append((pf.poses.copy(), pf.mean.copy(), pf.cov.copy(), len(pf.clusters)))
    (poses_a, mean_a, cov_a, n_a), (poses_b, mean_b, cov_b, n_b) = results
    assert np.array_equal(poses_a, poses_b)
    assert np.array_equal(mean_a, mean_b)
    assert np.array_equal(cov_a, cov_b)
    assert n_a == n_b
