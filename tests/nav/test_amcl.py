"""amcl's parts on their own: the odometry models' noise, the laser models' values on a
hand-made map, KLD-adaptive resampling, recovery, clusters and the estimate, and the same
output for the same seed."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest
from scipy import stats

from belvedere.maps import OccupancyMap
from belvedere.nav.amcl import (
    AmclMap,
    AmclParams,
    LaserData,
    LaserModel,
    LaserParams,
    Localizer,
    ParticleFilter,
    laser_data,
    resample_limit,
    sample_motion,
)

Floats = npt.NDArray[np.float64]
N = 200_000
ALPHAS = (0.01, 0.02, 0.03, 0.04, 0.05)


def _moved(model: str, delta: tuple[float, float, float], start_yaw: float = 0.0) -> Floats:
    """N particles at the origin heading ``start_yaw`` after the odometry's step ``delta``
    (given in the odometry frame, which here is the particles' frame)."""
    poses = np.zeros((N, 3))
    poses[:, 2] = start_yaw
    odom = np.array([delta[0], delta[1], start_yaw + delta[2]])
    sample_motion(model, ALPHAS, poses, odom, delta, np.random.default_rng(1))
    return poses


# --- odometry models -----------------------------------------------------------------------------
def test_diff_corrected_spreads_a_straight_step_by_the_square_roots() -> None:
    a1, a2, a3, a4, _ = ALPHAS
    poses = _moved("diff-corrected", (1.0, 0.0, 0.0))
    trans = np.hypot(poses[:, 0], poses[:, 1])
    assert trans.mean() == pytest.approx(1.0, abs=0.005)
    # no turn: only translation adds noise, sqrt(a3·t²) along, sqrt(a2·t²) in both turns
    assert trans.std() == pytest.approx(math.sqrt(a3), rel=0.02)
    assert poses[:, 2].std() == pytest.approx(math.sqrt(2 * a2), rel=0.02)
    del a1, a4


def test_diff_passes_the_variance_as_the_deviation_as_amcl_does() -> None:
    a3 = ALPHAS[2]
    poses = _moved("diff", (0.5, 0.0, 0.0))
    trans = np.hypot(poses[:, 0], poses[:, 1])
    assert trans.std() == pytest.approx(a3 * 0.25, rel=0.02)  # not sqrt(a3)·0.5


def test_diff_treats_driving_backwards_like_forwards() -> None:
    forward = _moved("diff-corrected", (0.5, 0.0, 0.0))
    backward = _moved("diff-corrected", (-0.5, 0.0, 0.0))
    assert backward[:, 0].mean() == pytest.approx(-0.5, abs=0.005)
    assert np.hypot(*backward[:, :2].T).std() == pytest.approx(
        np.hypot(*forward[:, :2].T).std(), rel=0.02
    )


def test_diff_turning_in_place_has_no_bearing_and_rotation_noise() -> None:
    a1, _, _, a4, _ = ALPHAS
    poses = _moved("diff-corrected", (0.0, 0.0, 0.6))
    assert poses[:, 2].mean() == pytest.approx(0.6, abs=0.005)
    assert poses[:, 2].std() == pytest.approx(math.sqrt(a1) * 0.6, rel=0.02)
    assert np.hypot(*poses[:, :2].T).mean() == pytest.approx(
        math.sqrt(a4) * 0.6 * math.sqrt(2 / math.pi), rel=0.02
    )


def test_omni_strafes_with_alpha5() -> None:
    _, a2, a3, _, a5 = ALPHAS
    for model, spread in (("omni", lambda v: v), ("omni-corrected", math.sqrt)):
        poses = _moved(model, (0.0, 0.5, 0.0), start_yaw=0.3)  # sideways-ish, robot turned
        # the step is along the odometry frame's y, which is the particles' frame here
        along, across = poses[:, 1], -poses[:, 0]
        assert along.mean() == pytest.approx(0.5, abs=0.005)
        assert along.std() == pytest.approx(spread(a3 * 0.25), rel=0.02)
        assert across.std() == pytest.approx(spread(a5 * 0.25), rel=0.02)
        assert (poses[:, 2] - 0.3).std() == pytest.approx(spread(a2 * 0.25), rel=0.02)


def test_an_unknown_odometry_model_is_refused() -> None:
    with pytest.raises(ValueError, match="unknown odometry model 'tank'"):
        _moved("tank", (0.1, 0.0, 0.0))


# --- laser models --------------------------------------------------------------------------------
def _room() -> AmclMap:
    """20 x 20 cells of 0.1 m from (0, 0), free, with a wall along column 15 (x 1.5-1.6 m)."""
    data = np.zeros((20, 20), dtype=np.int8)
    data[:, 15] = 100
    data[0, 0] = -1
    return AmclMap.from_occupancy(OccupancyMap(data, 0.1))


def _scan(*ranges: float, bearings: tuple[float, ...] = (), range_max: float = 4.0) -> LaserData:
    angles = bearings or tuple(0.0 for _ in ranges)
    return LaserData(np.array(ranges), np.array(angles), range_max)


def _pz(dist: float, params: LaserParams, range_max: float = 4.0) -> float:
    hit = params.z_hit * math.exp(-(dist**2) / (2 * params.sigma_hit**2))
    return hit + params.z_rand / range_max


def test_the_likelihood_field_scores_the_beam_ends_distance_to_the_wall() -> None:
    params = LaserParams(max_beams=2)
    model = LaserModel(params, _room())
    pose = np.array([[0.55, 1.05, 0.0]])  # in cell (5, 10), facing the wall
    # a beam ending in cell (12, 10): three cells (0.3 m) from the wall's cells
    weights = model.weigh(pose, (0.0, 0.0, 0.0), _scan(0.7, 0.7))
    assert weights[0] == pytest.approx(1.0 + 2 * _pz(0.3, params) ** 3, rel=1e-5)
    # the laser 0.2 m ahead on the base puts the ends 0.1 m from the wall
    weights = model.weigh(pose, (0.2, 0.0, 0.0), _scan(0.7, 0.7))
    assert weights[0] == pytest.approx(1.0 + 2 * _pz(0.1, params) ** 3, rel=1e-5)
    # turned by the laser's yaw (pi: facing away, ending off the map: the maximum distance)
    weights = model.weigh(pose, (0.0, 0.0, math.pi), _scan(0.7, 0.7))
    assert weights[0] == pytest.approx(1.0 + 2 * _pz(2.0, params) ** 3, rel=1e-5)
    # readings at the range's end are left out
    assert model.weigh(pose, (0.0, 0.0, 0.0), _scan(4.0, 4.0))[0] == 1.0


def test_the_likelihood_field_caps_the_distance() -> None:
    params = LaserParams(max_beams=2, likelihood_max_dist=0.2)
    model = LaserModel(params, _room())
    weights = model.weigh(np.array([[0.55, 1.05, 0.0]]), (0.0, 0.0, 0.0), _scan(0.3, 0.3))
    assert weights[0] == pytest.approx(1.0 + 2 * _pz(0.2, params) ** 3, rel=1e-5)


def test_likelihood_field_prob_multiplies_the_beams() -> None:
    params = LaserParams(model="likelihood_field_prob", max_beams=2)
    model = LaserModel(params, _room())
    pose = np.array([[0.55, 1.05, 0.0]])
    weights = model.weigh(pose, (0.0, 0.0, 0.0), _scan(0.7, 0.9))
    assert weights[0] == pytest.approx(_pz(0.3, params) * _pz(0.1, params), rel=1e-5)


def test_beam_skipping_leaves_out_beams_most_particles_disagree_on() -> None:
    params = LaserParams(
        model="likelihood_field_prob", max_beams=3, do_beamskip=True, beam_skip_distance=0.15
    )
    model = LaserModel(params, _room())
    poses = np.array([[0.55, 1.05, 0.0], [0.55, 1.15, 0.0], [0.65, 1.05, 0.0]])
    # beams 1 and 3 end at the wall for all; beam 2 far short of it (an unmapped obstacle)
    scan = _scan(1.0, 0.2, 1.0)
    skipped = model.weigh(poses, (0.0, 0.0, 0.0), scan, converged=True)
    assert model.skipped_beams == 1
    assert skipped[0] == pytest.approx(_pz(0.0, params) ** 2, rel=1e-5)
    # not converged: every beam counts
    full = model.weigh(poses, (0.0, 0.0, 0.0), scan, converged=False)
    assert model.skipped_beams == 0
    assert full[0] == pytest.approx(_pz(0.0, params) ** 2 * _pz(0.8, params), rel=1e-5)
    # too many beams disagree: the filter is probably wrong, so all count again
    wrong = model.weigh(poses, (0.0, 0.0, 0.0), _scan(0.2, 0.2, 0.2), converged=True)
    assert model.skipped_beams == 0
    assert wrong[0] == pytest.approx(_pz(0.8, params) ** 3, rel=1e-5)


def test_the_beam_model_casts_rays_to_the_first_non_free_cell() -> None:
    params = LaserParams(model="beam", max_beams=2)
    model = LaserModel(params, _room())
    pose = np.array([[0.55, 1.05, 0.0]])
    expected = model.expected_ranges(pose, (0.0, 0.0, 0.0), np.array([0.0, math.pi]), 4.0)
    # the wall's first cell starts at x = 1.5; the map's edge behind at x = 0
    assert expected[0, 0] == pytest.approx(0.95, abs=0.05)
    assert expected[0, 1] == pytest.approx(0.55, abs=0.05)
    exact = float(expected[0, 0])

    def pz(obs: float) -> float:
        z = obs - exact
        p = params.z_hit * math.exp(-(z * z) / (2 * params.sigma_hit**2))
        if z < 0:
            p += params.z_short * params.lambda_short * math.exp(-params.lambda_short * obs)
        p += params.z_max if obs == 4.0 else params.z_rand / 4.0
        return p

    for obs in (exact, 0.5, 4.0):
        weights = model.weigh(pose, (0.0, 0.0, 0.0), _scan(obs, bearings=(0.0,)))
        assert weights[0] == pytest.approx(1.0 + pz(obs) ** 3, rel=1e-6)


def test_which_beams_the_models_use() -> None:
    model = LaserModel(LaserParams(max_beams=60), _room())
    scan = laser_data(np.full(360, 1.0), -math.pi, math.radians(1.0), 0.1, 4.0)
    ranges, bearings = model.beams(scan)
    assert len(ranges) == 60  # every (360 - 1) // (60 - 1) = 6th beam
    assert np.allclose(np.diff(bearings), math.radians(6.0))
    # readings at or under the minimum count as maximum-range readings
    data = laser_data([0.05, 0.1, 0.5, 9.0], 0.0, 0.1, 0.1, 4.0)
    assert data.ranges.tolist() == [4.0, 4.0, 0.5, 9.0]
    narrowed = laser_data(
        [0.05, 0.3, 2.5], 0.0, 0.1, 0.1, 4.0, laser_min_range=0.4, laser_max_range=2.0
    )
    assert narrowed.range_max == 2.0
    assert narrowed.ranges.tolist() == [2.0, 2.0, 2.5]


# --- the filter ----------------------------------------------------------------------------------
def _filter(
    min_samples: int = 100, max_samples: int = 5000, amap: AmclMap | None = None, **kw: float
) -> ParticleFilter:
    amap = amap or _room()
    return ParticleFilter(
        min_samples,
        max_samples,
        alpha_slow=kw.get("alpha_slow", 0.0),
        alpha_fast=kw.get("alpha_fast", 0.0),
        random_poses=amap.random_poses,
        rng=np.random.default_rng(3),
        pop_err=kw.get("pop_err", 0.01),
        pop_z=kw.get("pop_z", 0.99),
    )


def test_the_kld_bound_is_the_chi_square_quantile() -> None:
    z = stats.norm.ppf(0.99)
    for k in (10, 50, 200):
        exact = stats.chi2.ppf(0.99, k - 1) / (2 * 0.01)
        assert resample_limit(k, 0.01, z, 1, 10**9) == pytest.approx(exact, rel=0.01)
    limits = resample_limit(np.array([0, 1, 2, 5, 10_000]), 0.01, 0.99, 100, 5000)
    assert limits.tolist()[:2] == [5000, 5000]  # one bin or none: as many as allowed
    assert limits[2] == 100  # the floor
    assert limits[-1] == 5000  # the ceiling


def test_resampling_stops_one_past_the_bound_for_the_bins_filled() -> None:
    pf = _filter()
    # particles in exactly two bins: the bound is min_samples, amcl stops one draw past it
    pf.poses = np.array([[0.1, 0.1, 0.05], [0.7, 0.1, 0.05]] * 2500)
    pf.weights = np.full(5000, 1 / 5000)
    pf.resample()
    assert pf.count == 101
    # spread particles fill many bins and keep many particles
    pf.poses = np.column_stack(
        [np.linspace(0, 1.9, 5000), np.linspace(0, 1.9, 5000)[::-1], np.linspace(-3, 3, 5000)]
    )
    pf.weights = np.full(5000, 1 / 5000)
    pf.resample()
    bins = len({tuple(k) for k in np.floor(pf.poses / [0.5, 0.5, math.radians(10)]).astype(int)})
    assert pf.count == min(int(resample_limit(bins, 0.01, 0.99, 100, 5000)) + 1, 5000)
    assert pf.count > 1000


def test_resampling_draws_by_weight() -> None:
    pf = _filter(min_samples=5000)
    pf.poses = np.array([[0.1, 0.1, 0.0], [1.1, 1.1, 0.0]] * 2500)
    pf.weights = np.where(np.arange(5000) % 2 == 0, 0.8, 0.2) / 2500
    pf.resample()
    share = float((pf.poses[:, 0] < 0.5).mean())
    assert share == pytest.approx(0.8, abs=0.02)
    assert np.allclose(pf.weights, 1 / pf.count)


def test_recovery_injects_random_free_poses_when_the_likelihood_drops() -> None:
    data = np.zeros((200, 200), dtype=np.int8)  # 20 m square, a wall and an unknown corner
    data[:, 150] = 100
    data[:20, :20] = -1
    amap = AmclMap.from_occupancy(OccupancyMap(data, 0.1))
    pf = _filter(2000, 2000, amap, alpha_slow=0.001, alpha_fast=0.5)
    pf.init_gaussian([1.0, 1.0, 0.0], np.diag([0.01, 0.01, 0.01]))
    pf.update_sensor(np.full(2000, 10.0))  # the averages start here
    pf.update_sensor(np.full(2000, 1.0))  # the likelihood falls tenfold
    w_diff = 1.0 - pf.w_fast / pf.w_slow
    assert w_diff > 0.3
    pf.resample()
    far = np.hypot(pf.poses[:, 0] - 1.0, pf.poses[:, 1] - 1.0) > 0.8
    assert far.mean() == pytest.approx(w_diff, abs=0.05)
    # only in free cells: never in the wall's column nor the unknown corner
    cols = np.floor(pf.poses[far, 0] / 0.1).astype(int)
    rows = np.floor(pf.poses[far, 1] / 0.1).astype(int)
    assert not (cols == 150).any()
    assert not ((cols < 20) & (rows < 20)).any()
    assert pf.poses[far, 0].max() > 15.0  # beyond the wall too
    assert pf.w_slow == pf.w_fast == 0.0  # reset after injecting


def test_clusters_and_the_estimate() -> None:
    pf = _filter()
    rng = np.random.default_rng(0)
    a = np.column_stack(
        [rng.normal(0.3, 0.05, 600), rng.normal(0.3, 0.05, 600), rng.normal(0.2, 0.02, 600)]
    )
    b = np.column_stack(
        [rng.normal(1.7, 0.05, 400), rng.normal(1.2, 0.05, 400), rng.normal(-1.0, 0.02, 400)]
    )
    pf.poses = np.vstack([a, b])
    pf.weights = np.full(1000, 1 / 1000)
    pf.update_clusters()
    assert len(pf.clusters) == 2
    best = pf.best_cluster()
    assert best is not None
    assert best.weight == pytest.approx(0.6)
    assert best.count == 600
    assert best.mean[:2] == pytest.approx(a[:, :2].mean(axis=0))
    assert best.mean[2] == pytest.approx(math.atan2(np.sin(a[:, 2]).mean(), np.cos(a[:, 2]).mean()))
    # the whole set's covariance: weighted, biased; the angle's from the mean resultant length
    assert pf.cov[:2, :2] == pytest.approx(np.cov(pf.poses[:, :2].T, bias=True))
    resultant = math.hypot(np.cos(pf.poses[:, 2]).mean(), np.sin(pf.poses[:, 2]).mean())
    assert pf.cov[2, 2] == pytest.approx(-2 * math.log(resultant))


def test_the_initial_gaussian_has_the_covariance_asked_for() -> None:
    pf = _filter(max_samples=100_000)
    cov = np.array([[0.25, 0.1, 0.0], [0.1, 0.16, 0.0], [0.0, 0.0, 0.04]])
    pf.init_gaussian([1.0, 2.0, 0.5], cov)
    assert pf.count == 100_000
    assert pf.poses.mean(axis=0) == pytest.approx([1.0, 2.0, 0.5], abs=0.01)
    assert np.cov(pf.poses.T) == pytest.approx(cov, abs=0.005)
    assert not pf.converged


# --- the localizer -------------------------------------------------------------------------------
def _run(seed: int) -> Localizer:
    grid = OccupancyMap(np.where(_room().states == 1, 100, 0).astype(np.int8), 0.1)
    params = AmclParams(
        min_particles=200,
        max_particles=1000,
        initial_pose_x=0.8,
        initial_pose_y=1.0,
        resample_interval=1,
    )
    loc = Localizer(params, grid, seed=seed)
    scan = laser_data(np.full(30, 0.7), -0.3, 0.02, 0.1, 4.0)
    for k in range(8):
        loc.update(np.array([0.05 * k, 0.0, 0.0]), scan, (0.0, 0.0, 0.0))
    return loc


def test_the_same_seed_gives_the_same_particles() -> None:
    a, b, c = _run(5), _run(5), _run(6)
    assert np.array_equal(a.filter.poses, b.filter.poses)
    assert a.estimate is not None
    assert b.estimate is not None
    assert np.array_equal(a.estimate.pose, b.estimate.pose)
    assert not np.array_equal(a.filter.poses[:10], c.filter.poses[:10])


def test_the_filter_updates_after_enough_motion_and_resamples_every_interval() -> None:
    grid = OccupancyMap(np.zeros((20, 20), dtype=np.int8), 0.1)
    params = AmclParams(update_min_d=0.2, update_min_a=0.5, resample_interval=2)
    loc = Localizer(params, grid, seed=0)
    scan = laser_data(np.full(10, 4.0), 0.0, 0.1, 0.1, 4.0)
    laser = (0.0, 0.0, 0.0)
    first = loc.update(np.zeros(3), scan, laser)
    assert first.updated
    assert not first.resampled
    assert first.estimate is not None  # published on the first scan
    assert not loc.update(np.array([0.15, 0.15, 0.0]), scan, laser).updated  # each axis < 0.2
    moved = loc.update(np.array([0.25, 0.0, 0.0]), scan, laser)
    assert moved.updated
    assert moved.resampled  # the second update
    assert not loc.update(np.array([0.25, 0.0, 0.4]), scan, laser).updated
    assert loc.update(np.array([0.25, 0.0, 0.6]), scan, laser).updated
    loc.request_nomotion_update()
    assert loc.update(np.array([0.25, 0.0, 0.6]), scan, laser).updated


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"min_particles": 0}, "parameter min_particles: expected at least 1, got 0"),
        ({"kld_err": 1.5}, "parameter kld_err: expected a number between 0 and 1, got 1.5"),
        ({"laser_max_beams": 1}, "parameter laser_max_beams: expected at least 2, got 1"),
        ({"resample_interval": 0.5}, "parameter resample_interval: expected an integer, got 0.5"),
        ({"do_beamskip": "yes"}, "parameter do_beamskip: expected true or false, got 'yes'"),
        ({"laser_sigma_hit": 0}, "parameter laser_sigma_hit: expected a positive number, got 0.0"),
    ],
)
def test_bad_parameters_are_named(values: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=f"^{message}$"):
        AmclParams.from_mapping(values)
