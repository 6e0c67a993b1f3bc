"""amcl's per-scan logic without topics: when the filter updates (``update_min_d``/``_a``,
or a requested no-motion update), the odometry model, the laser model, every
``resample_interval``-th update a resampling, and the estimate it publishes.

Poses are (x, y, yaw); the odometry pose is the base's in the odometry frame at the scan's
stamp; the estimate is the base's in the map frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.maps import OccupancyMap
from belvedere.nav.amcl._filter import ParticleFilter
from belvedere.nav.amcl._laser import LASER_MODELS, LaserData, LaserModel, LaserParams
from belvedere.nav.amcl._map import AmclMap
from belvedere.nav.amcl._motion import ODOM_MODELS, angle_diff, sample_motion

__all__ = ["AmclParams", "Estimate", "Localizer", "Step"]

Floats = npt.NDArray[np.float64]

_LASER = LaserParams()


@dataclass(frozen=True)
class AmclParams:
    """The filter's parameters under amcl's names, with amcl's defaults."""

    min_particles: int = 100
    max_particles: int = 5000
    kld_err: float = 0.01
    kld_z: float = 0.99
    update_min_d: float = 0.2
    update_min_a: float = math.pi / 6.0
    resample_interval: int = 2
    recovery_alpha_slow: float = 0.001
    recovery_alpha_fast: float = 0.1
    selective_resampling: bool = False
    initial_pose_x: float = 0.0
    initial_pose_y: float = 0.0
    initial_pose_a: float = 0.0
    initial_cov_xx: float = 0.5 * 0.5
    initial_cov_yy: float = 0.5 * 0.5
    initial_cov_aa: float = (math.pi / 12.0) ** 2
    laser_min_range: float = -1.0
    laser_max_range: float = -1.0
    # the laser model's defaults are amcl's too: they are kept once, in LaserParams
    laser_max_beams: int = _LASER.max_beams
    laser_model_type: str = _LASER.model
    laser_z_hit: float = _LASER.z_hit
    laser_z_short: float = _LASER.z_short
    laser_z_max: float = _LASER.z_max
    laser_z_rand: float = _LASER.z_rand
    laser_sigma_hit: float = _LASER.sigma_hit
    laser_lambda_short: float = _LASER.lambda_short
    laser_likelihood_max_dist: float = _LASER.likelihood_max_dist
    do_beamskip: bool = _LASER.do_beamskip
    beam_skip_distance: float = _LASER.beam_skip_distance
    beam_skip_threshold: float = _LASER.beam_skip_threshold
    beam_skip_error_threshold: float = _LASER.beam_skip_error_threshold
    odom_model_type: str = "diff"
    odom_alpha1: float = 0.2
    odom_alpha2: float = 0.2
    odom_alpha3: float = 0.2
    odom_alpha4: float = 0.2
    odom_alpha5: float = 0.2

    @classmethod
    def names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> AmclParams:
        """The parameters in ``values`` (others keep their defaults; unknown names are
        ignored, as amcl ignores them). A bad value raises ValueError naming it."""
        defaults = cls()
        chosen: dict[str, Any] = {}
        for f in fields(cls):
            if f.name not in values:
                continue
            default = getattr(defaults, f.name)
            chosen[f.name] = _coerce(f.name, values[f.name], default)
        params = replace(defaults, **chosen)
        params.check()
        return params

    def check(self) -> None:
        """ValueError naming the first parameter whose value amcl cannot work with."""

        def bad(name: str, expected: str) -> None:
            msg = f"parameter {name}: expected {expected}, got {getattr(self, name)!r}"
            raise ValueError(msg)

        if self.min_particles < 1:
            bad("min_particles", "at least 1")
        if self.max_particles < self.min_particles:
            bad("max_particles", f"at least min_particles ({self.min_particles})")
        if not 0.0 < self.kld_err < 1.0:
            bad("kld_err", "a number between 0 and 1")
        if self.resample_interval < 1:
            bad("resample_interval", "at least 1")
        if self.laser_max_beams < 2:
            bad("laser_max_beams", "at least 2")
        if self.laser_model_type not in LASER_MODELS:
            bad("laser_model_type", "one of " + ", ".join(LASER_MODELS))
        if self.odom_model_type not in ODOM_MODELS:
            bad("odom_model_type", "one of " + ", ".join(ODOM_MODELS))
        if not self.laser_sigma_hit > 0.0:
            bad("laser_sigma_hit", "a positive number")
        if not self.laser_likelihood_max_dist > 0.0:
            bad("laser_likelihood_max_dist", "a positive number")
        for name in ("recovery_alpha_slow", "recovery_alpha_fast"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                bad(name, "a number from 0 to 1")
        for name in ("laser_z_hit", "laser_z_short", "laser_z_max", "laser_z_rand"):
            if getattr(self, name) < 0.0:
                bad(name, "a number of at least 0")
        for name in ("update_min_d", "update_min_a", "laser_lambda_short"):
            if getattr(self, name) < 0.0:
                bad(name, "a number of at least 0")

    def laser(self) -> LaserParams:
        return LaserParams(
            model=self.laser_model_type,
            max_beams=self.laser_max_beams,
            z_hit=self.laser_z_hit,
            z_short=self.laser_z_short,
            z_max=self.laser_z_max,
            z_rand=self.laser_z_rand,
            sigma_hit=self.laser_sigma_hit,
            lambda_short=self.laser_lambda_short,
            likelihood_max_dist=self.laser_likelihood_max_dist,
            do_beamskip=self.do_beamskip,
            beam_skip_distance=self.beam_skip_distance,
            beam_skip_threshold=self.beam_skip_threshold,
            beam_skip_error_threshold=self.beam_skip_error_threshold,
        )

    def initial_pose(self) -> tuple[Floats, Floats]:
        mean = np.array([self.initial_pose_x, self.initial_pose_y, self.initial_pose_a])
        cov = np.diag([self.initial_cov_xx, self.initial_cov_yy, self.initial_cov_aa])
        return mean, cov


def _coerce(name: str, value: Any, default: Any) -> Any:
    """``value`` as the parameter's type (ints may stand for floats, as the parameter server
    lets them), or ValueError naming the parameter."""
    kind = type(default)
    if kind is bool:
        if isinstance(value, bool):
            return value
        expected = "true or false"
    elif kind is int:
        if isinstance(value, int) and not isinstance(value, bool):
            return value
        expected = "an integer"
    elif kind is float:
        if isinstance(value, int | float) and not isinstance(value, bool):
            return float(value)
        expected = "a number"
    else:
        if isinstance(value, str):
            return value
        expected = "a string"
    msg = f"parameter {name}: expected {expected}, got {value!r}"
    raise ValueError(msg)


@dataclass(frozen=True)
class Estimate:
    """The heaviest cluster's mean (x, y, yaw) and the whole set's covariance (3x3), as
    amcl fills ``amcl_pose``."""

    pose: Floats
    cov: Floats

    def covariance36(self) -> list[float]:
        """The 6x6 row-major covariance of ``PoseWithCovariance`` (x, y and yaw filled)."""
        out = [0.0] * 36
        for i in range(2):
            for j in range(2):
                out[6 * i + j] = float(self.cov[i, j])
        out[35] = float(self.cov[2, 2])
        return out


@dataclass(frozen=True)
class Step:
    """What one scan did: whether the filter took it (``updated``), resampled, and the
    estimate amcl publishes then (after a resampling or the first scan), else None."""

    updated: bool
    resampled: bool
    estimate: Estimate | None


class Localizer:
    """One map's filter, fed scans with the odometry at their stamps."""

    def __init__(self, params: AmclParams, grid: OccupancyMap | AmclMap, *, seed: int = 0):
        self.params = params
        self.map = grid if isinstance(grid, AmclMap) else AmclMap.from_occupancy(grid)
        self.rng = np.random.default_rng(seed)
        self.filter = ParticleFilter(
            params.min_particles,
            params.max_particles,
            alpha_slow=params.recovery_alpha_slow,
            alpha_fast=params.recovery_alpha_fast,
            random_poses=self.map.random_poses,
            rng=self.rng,
            pop_err=params.kld_err,
            pop_z=params.kld_z,
            selective_resampling=params.selective_resampling,
        )
        self.laser = LaserModel(params.laser(), self.map)
        self.alphas = (
            params.odom_alpha1,
            params.odom_alpha2,
            params.odom_alpha3,
            params.odom_alpha4,
            params.odom_alpha5,
        )
        self.initialized = False
        """Whether the filter has an odometry pose to measure motion from (amcl's
        ``pf_init_``); a new initial pose clears it."""
        self.odom_pose: Floats = np.zeros(3)
        self.force_update = False
        self.resample_count = 0
        self.estimate: Estimate | None = None
        self.filter.init_gaussian(*params.initial_pose())

    # --- what services and topics ask --------------------------------------------------------
    def set_pose(self, mean: npt.ArrayLike, cov: npt.ArrayLike) -> None:
        """Particles about a pose (``initialpose``, ``set_map``'s initial pose)."""
        self.filter.init_gaussian(mean, cov)
        self.initialized = False

    def global_localization(self) -> None:
        """Particles uniform over the map's free cells."""
        self.filter.init_model()
        self.initialized = False

    def request_nomotion_update(self) -> None:
        """The next scan updates the filter though the robot has not moved."""
        self.force_update = True

    # --- the scan ----------------------------------------------------------------------------
    def update(
        self, odom_pose: npt.ArrayLike, data: LaserData, laser_pose: tuple[float, float, float]
    ) -> Step:
        """One scan with the base's odometry pose at its stamp and the laser's pose on the
        base (x, y, yaw; amcl folds the laser's yaw into the bearings and passes 0)."""
        pose = np.asarray(odom_pose, dtype=np.float64)
        delta = np.array(
            [
                pose[0] - self.odom_pose[0],
                pose[1] - self.odom_pose[1],
                angle_diff(float(pose[2]), float(self.odom_pose[2])),
            ]
        )
        p = self.params
        update = False
        first = False
        if self.initialized:
            update = bool(
                abs(delta[0]) > p.update_min_d
                or abs(delta[1]) > p.update_min_d
                or abs(delta[2]) > p.update_min_a
                or self.force_update
            )
            self.force_update = False
        else:
            self.odom_pose = pose
            self.initialized = True
            update = first = True
            self.resample_count = 0
        if update and not first:
            sample_motion(p.odom_model_type, self.alphas, self.filter.poses, pose, delta, self.rng)
        resampled = False
        if update:
            # once for the laser model and the clusters' mean yaw after resampling
            poses = self.filter.poses
            headings = np.cos(poses[:, 2]), np.sin(poses[:, 2])
            factors = self.laser.weigh(
                poses, laser_pose, data, converged=self.filter.converged, headings=headings
            )
            self.filter.update_sensor(factors)
            self.odom_pose = pose
            self.resample_count += 1
            if self.resample_count % p.resample_interval == 0:
                self.filter.resample(headings)
                resampled = True
        estimate = None
        if resampled or first:
            best = self.filter.best_cluster()
            if best is not None:
                estimate = Estimate(best.mean.copy(), self.filter.cov.copy())
                self.estimate = estimate
        return Step(update, resampled, estimate)
