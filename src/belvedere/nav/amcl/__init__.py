"""amcl — adaptive Monte Carlo localization on a known map — over plain arrays.

:class:`Localizer` is amcl's per-scan logic (:class:`AmclParams` under amcl's parameter
names); :class:`ParticleFilter`, :class:`LaserModel` and :func:`sample_motion` are its parts.
"""

from belvedere.nav.amcl._filter import BIN_SIZE, Cluster, ParticleFilter, resample_limit
from belvedere.nav.amcl._laser import LASER_MODELS, LaserData, LaserModel, LaserParams, laser_data
from belvedere.nav.amcl._localizer import AmclParams, Estimate, Localizer, Step
from belvedere.nav.amcl._map import FREE, OCCUPIED, UNKNOWN, AmclMap
from belvedere.nav.amcl._motion import ODOM_MODELS, angle_diff, sample_motion

__all__ = [
    "BIN_SIZE",
    "FREE",
    "LASER_MODELS",
    "OCCUPIED",
    "ODOM_MODELS",
    "UNKNOWN",
    "AmclMap",
    "AmclParams",
    "Cluster",
    "Estimate",
    "LaserData",
    "LaserModel",
    "LaserParams",
    "Localizer",
    "ParticleFilter",
    "Step",
    "angle_diff",
    "laser_data",
    "resample_limit",
    "sample_motion",
]
