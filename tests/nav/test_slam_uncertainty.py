"""The gmapping node's pose uncertainty: GMapping's likelihood sampling around each match
(``lsigma``, ``ogain``, ``llsamplerange``/``llsamplestep``, ``lasamplerange``/``lasamplestep``)
gives the covariance and the entropy, never the trajectory or the map; the particle filter's
own parameters draw one warning when they are set.

Scans are ray-cast in the ring of corridors of ``corridor_loop``: its bare south corridor (two
straight walls 2 m apart, nothing else within the laser's 6 m) and its south-west corner, where
the run begins (walls on every side, and boxes).
"""

from __future__ import annotations

import copy
import logging
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.cli import main
from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.nav.slam import GMappingParams, LaserGeometry, SubmapSlam
from belvedere.nav.slam._grid import FieldGrid
from belvedere.nav.slam._proposal import lattice
from belvedere.packages import PackageIndex
from tests.nav import corridor_loop, simulated

LASER = LaserGeometry.planar(
    float(corridor_loop.ANGLES[0]),
    float(corridor_loop.ANGLES[1] - corridor_loop.ANGLES[0]),
    len(corridor_loop.ANGLES),
    *corridor_loop.RANGE,
)
CORRIDOR = [(12.0 + 0.1 * k, 1.0, 0.0) for k in range(6)]
"""Along the bare south corridor (its walls at y = 0 and y = 2), facing along it (+x)."""
CORNER = [(2.5 + 0.08 * k, 1.0 + 0.02 * k, 0.03 * k) for k in range(6)]
"""In the south-west corner, where the run begins."""
WIDE = {"llsamplerange": 0.1, "llsamplestep": 0.02, "lasamplerange": 0.02, "lasamplestep": 0.005}
"""A lattice wide enough that the scan's likelihood shapes the weights."""


def _mapped(poses: list[tuple[float, float, float]], **params: Any) -> SubmapSlam:
    """A mapper fed scans at ``poses`` (the odometry exact): the first makes the map, the
    others are matched against it."""
    rng = np.random.default_rng(5)
    slam = SubmapSlam(LASER, GMappingParams.from_mapping(params))
    for k, pose in enumerate(poses):
        slam.add_scan(k * 0.2, corridor_loop.ranges(np.array(pose), rng), np.array(pose))
    return slam


def test_the_lattice_is_symmetric_about_the_match_and_through_it() -> None:
    assert np.allclose(lattice(0.01, 0.01), [-0.01, 0.0, 0.01])
    assert np.allclose(lattice(0.01, 0.004), [-0.008, -0.004, 0.0, 0.004, 0.008])
    assert np.allclose(lattice(0.0, 0.01), [0.0])
    assert np.allclose(lattice(0.01, 0.05), [0.0])  # a step beyond the range: the match alone


def test_a_corridor_leaves_the_pose_uncertain_along_it_not_across_it() -> None:
    default = _mapped(CORRIDOR).covariance()
    wide = _mapped(CORRIDOR, **WIDE).covariance()
    # slam_gmapping's default lattice (±1 cm) is too small for the walls to shape it
    assert default[0, 0] == pytest.approx(default[1, 1], rel=0.05)
    # a wider one: along the corridor every sample fits as well, across it they do not
    assert wide[0, 0] > 5 * wide[1, 1]
    assert wide[0, 0] > 20 * default[0, 0]
    # (nearly the lattice's own spread along it: all 11 samples weigh nearly the same; the
    # farthest put a few end points past the walls the first scan saw)
    assert 0.8 * np.var(lattice(0.1, 0.02)) < wide[0, 0] <= np.var(lattice(0.1, 0.02))
    corner = _mapped(CORNER, **WIDE).covariance()
    assert corner[0, 0] < wide[0, 0] / 3  # the corner pins it down both ways
    assert np.allclose(wide, wide.T)
    assert np.all(np.linalg.eigvalsh(wide) > 0)


@pytest.mark.parametrize("name", ["lsigma", "ogain"])
def test_a_larger_lsigma_or_ogain_flattens_the_weights(name: str) -> None:
    base = GMappingParams().lsigma if name == "lsigma" else GMappingParams().ogain
    runs = [_mapped(CORNER, **WIDE, **{name: base * f}) for f in (1, 4, 16)]
    entropy = [slam.entropy() for slam in runs]
    assert entropy[0] < entropy[1] < entropy[2]
    variances = [np.diag(slam.covariance()) for slam in runs]
    assert np.all(variances[0] < variances[1])
    assert np.all(variances[1] < variances[2])


def test_lsigma_and_ogain_act_through_their_product() -> None:
    a = _mapped(CORNER, **WIDE, lsigma=0.15, ogain=3.0).covariance()
    b = _mapped(CORNER, **WIDE, lsigma=0.075, ogain=6.0).covariance()
    assert np.allclose(a, b, rtol=1e-9, atol=0.0)


def test_an_axis_sampled_once_takes_the_matchs_own_variance() -> None:
    # nothing sampled: the match's least-squares covariance whole
    none = _mapped(CORNER, llsamplerange=0.0, lasamplerange=0.0).covariance()
    assert np.all(np.linalg.eigvalsh(none) > 0)
    assert math.isfinite(_mapped(CORNER, llsamplerange=0.0, lasamplerange=0.0).entropy())
    # x and y sampled once (a range under the step): their block as before, the heading
    # from the lattice, uncorrelated with them
    heading = _mapped(CORNER, llsamplerange=0.01, llsamplestep=0.05).covariance()
    assert np.allclose(heading[:2, :2], none[:2, :2], rtol=1e-12, atol=0.0)
    assert np.all(heading[:2, 2] == 0.0)
    assert heading[2, 2] == pytest.approx(np.var(lattice(0.005, 0.005)), rel=0.05)
    # the heading sampled once: x and y from the lattice, the heading as before
    planar = _mapped(CORNER, lasamplerange=0.0).covariance()
    assert planar[2, 2] == pytest.approx(none[2, 2], rel=1e-12)
    assert np.all(planar[:2, 2] == 0.0)
    assert none[0, 0] < planar[0, 0] < np.var(lattice(0.01, 0.01))


def test_steps_must_be_positive_and_ranges_not_negative() -> None:
    with pytest.raises(ValueError, match="parameter llsamplestep must be positive, got 0"):
        GMappingParams.from_mapping({"llsamplestep": 0})
    with pytest.raises(ValueError, match="parameter lasamplestep must be positive"):
        GMappingParams.from_mapping({"lasamplestep": -0.01})
    with pytest.raises(ValueError, match="parameter lasamplerange must not be negative"):
        GMappingParams.from_mapping({"lasamplerange": -0.01})


def test_a_scan_added_to_the_map_is_judged_against_the_map_it_was_matched_to() -> None:
    # The second scan is added to the map in one run (a keyframe every scan), not in the
    # other; both were matched against the same map, so their uncertainty is the same.
    kept = _mapped(CORRIDOR[:2], **WIDE, temporalUpdate=0.0)
    not_kept = _mapped(CORRIDOR[:2], **WIDE)
    assert len(kept.keyframes) == 2
    assert len(not_kept.keyframes) == 1
    assert np.array_equal(kept.covariance(), not_kept.covariance())
    assert kept.covariance()[0, 0] > 5 * kept.covariance()[1, 1]  # not pinned by itself


def test_a_grid_undoes_its_last_insert_for_a_while() -> None:
    rng = np.random.default_rng(2)
    grid = FieldGrid(0.05, 0.05, 3)
    grid.insert(rng.uniform(-2, 2, (300, 2)))
    before = copy.deepcopy(grid)
    grid.insert(rng.uniform(-2, 9, (300, 2)), undoable=True)  # the grid grows
    after = copy.deepcopy(grid)
    probe = rng.uniform(-3, 10, (5000, 2))
    assert not np.array_equal(grid.sample(probe)[0], before.sample(probe)[0])
    with grid.before_last_insert():
        assert np.array_equal(grid.sample(probe)[0], before.sample(probe)[0])
    assert np.array_equal(grid.field, after.field)  # to the bit
    grid.finish()  # cropped, to float32: what it keeps is renumbered
    finished = grid.field.copy()
    with grid.before_last_insert():
        assert np.allclose(grid.sample(probe)[0], before.sample(probe)[0], atol=1e-6)
    assert np.array_equal(grid.field, finished)
    grid.insert(rng.uniform(-2, 2, (10, 2)))
    assert not grid.undoable
    with pytest.raises(RuntimeError, match="kept nothing to undo"), grid.before_last_insert():
        pass


def test_the_trajectory_and_the_map_do_not_depend_on_these_parameters() -> None:
    rec = corridor_loop.record(count=100)
    laser = simulated.laser_of(rec)

    def run(ask: bool, **params: Any) -> tuple[SubmapSlam, list[float]]:
        # a keyframe every 0.2 m: submaps are begun and finished within the run
        slam = SubmapSlam(laser, GMappingParams.from_mapping({"linearUpdate": 0.2, **params}))
        entropy = []
        for ns, scan, odom in zip(rec.stamps_ns, rec.scans, rec.odom, strict=True):
            done = slam.add_scan(ns / 1e9, np.asarray(scan.ranges), odom)
            assert done is not None
            if ask or done.keyframe:
                entropy.append(slam.entropy())
        return slam, entropy

    slam, _ = run(False)
    assert sum(sub.finished for sub in slam.submaps) >= 2
    poses, grid = slam.trajectory()[1], slam.occupancy().data
    small = {"llsamplerange": 0.04, "llsamplestep": 0.02, "lasamplerange": 0.01}
    cases: list[tuple[bool, dict[str, float]]] = [
        (True, {"particles": 80}),
        (True, {**small, "lsigma": 0.5, "ogain": 10.0}),
        (False, {"llsamplerange": 0.0, "lasamplerange": 0.0, "resampleThreshold": 0.1}),
    ]
    for ask, params in cases:
        other, entropy = run(ask, **params)
        assert np.array_equal(other.trajectory()[1], poses)
        assert np.array_equal(other.occupancy().data, grid)
        assert all(math.isfinite(e) for e in entropy)
        assert len(set(entropy)) > len(entropy) // 2  # it changes from scan to scan


def test_the_particle_filters_parameters_draw_one_warning_in_a_launch(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    def start(params: str) -> list[str]:
        launch = tmp_path / "slam.launch"
        launch.write_text(
            '<launch>\n  <node pkg="gmapping" type="slam_gmapping" name="slam_gmapping">\n'
            f"{params}  </node>\n</launch>\n"
        )
        packages = PackageIndex.from_environment(near=launch)
        caplog.clear()
        with caplog.at_level(logging.WARNING, logger="belvedere"):
            runtime = LaunchRuntime(
                load_launch(launch, packages=packages), Graph(), packages, headless=True
            )
            runtime.start()
        return [r.getMessage() for r in caplog.records if "no effect" in r.getMessage()]

    set_both = (
        '    <param name="particles" value="30"/>\n'
        '    <param name="lsigma" value="0.1"/>\n'
        '    <param name="resampleThreshold" value="0.5"/>\n'
    )
    assert start(set_both) == [
        f"{tmp_path / 'slam.launch'}:2:3: warning: /slam_gmapping: particles, "
        "resampleThreshold have no effect here: belvedere's mapper keeps one trajectory in a "
        "pose graph, not a particle filter"
    ]
    assert start('    <param name="lsigma" value="0.1"/>\n') == []
    assert start("") == []  # their defaults are no reason to warn


def test_belvedere_slam_warns_once_of_parameters_without_effect(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bag = tmp_path / "corridor.bag"
    simulated.write_bag(bag, corridor_loop.record(count=25))
    out = ["--base-frame", "base_footprint", "--trajectory", str(tmp_path / "t.tum")]
    assert main(["slam", str(bag), *out, "particles:=30", "seed:=4", "ogain:=2"]) == 0
    err = capsys.readouterr().err
    assert err.count("no effect") == 2  # one warning, two reasons
    assert err.count("warning: ") == 1
    assert (
        "warning: slam_gmapping: particles has no effect here: belvedere's mapper keeps one "
        "trajectory in a pose graph, not a particle filter; seed has no effect here: the "
        "mapper is deterministic and draws no random numbers\n"
    ) in err
    assert main(["slam", str(bag), *out, "ogain:=2", "llsamplerange:=0.05"]) == 0
    assert "no effect" not in capsys.readouterr().err
