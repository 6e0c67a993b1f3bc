"""slam_gmapping's parameters, with its names and defaults, and what each does here.

The mapper (:class:`belvedere.nav.slam.SubmapSlam`) is not GMapping's particle filter (see
:mod:`belvedere.nav.slam._slam` for why) but reads the same parameters, each with the same
intent where it has a counterpart:

``maxRange``
    Beams longer than this are dropped (no return). Default: the scan's ``range_max`` minus
    0.01 m, as slam_gmapping sets it from the first scan.
``maxUrange``
    Beams are used for matching and for the map's obstacles up to this range; longer ones
    (up to ``maxRange``) only clear the cells they cross. Default: ``maxRange``.
``sigma``, ``kernelSize``
    The matcher's likelihood field: a Gaussian of standard deviation ``sigma`` metres around
    every end point, cut ``kernelSize + 2`` cells away.
``lstep``, ``astep``, ``iterations``
    A match scoring under ``minimumScore`` is searched again (branch and bound) within
    ``iterations * lstep`` metres and ``iterations * astep`` radians of the prediction;
    ``2 * iterations`` bounds the Levenberg-Marquardt iterations of every match.
``lskip``
    Take every (lskip+1)-th beam for matching.
``minimumScore``
    GMapping's score is a sum over beams; here it is the mean field value at the end points
    times their number. A match under it is searched again as above, and if that fails too
    the odometry's prediction is kept. 0 accepts every match.
``srr``, ``srt``, ``str``, ``stt``
    The odometry error model (translation from translation, translation from rotation,
    rotation from rotation, rotation from translation): each match is pulled towards the
    odometry's prediction with standard deviations ``srr*d + str*|a|`` (m) and
    ``stt*|a| + srt*d`` (rad) for a step of ``d`` metres and ``a`` radians.
``linearUpdate``, ``angularUpdate``, ``temporalUpdate``
    A scan is added to the map (a keyframe) once the robot travelled ``linearUpdate`` metres
    or turned ``angularUpdate`` radians (summed along the way, as GMapping does), or
    ``temporalUpdate`` seconds passed if that is not negative. Every scan is still matched,
    so the trajectory has one pose per scan.
``xmin``, ``ymin``, ``xmax``, ``ymax``, ``delta``
    The map's initial extent (it grows to hold what is seen) and its resolution, which is
    also that of the grids scans are matched against.
``occ_thresh``, ``map_update_interval``, ``throttle_scans``
    The node's: a cell whose hits over visits exceed ``occ_thresh`` is occupied; a new map
    after ``map_update_interval`` seconds; only every ``throttle_scans``-th scan is used.
``lsigma``, ``ogain``, ``llsamplerange``, ``llsamplestep``, ``lasamplerange``, ``lasamplestep``
    The pose's uncertainty, as GMapping estimates its proposal (:mod:`._proposal`): the
    scan's likelihood at a lattice of poses around its match, x and y within
    ``llsamplerange`` metres in steps of ``llsamplestep``, the heading within
    ``lasamplerange`` radians in steps of ``lasamplestep``; a beam's log-likelihood is minus
    its end point's squared distance to the nearest wall over ``lsigma``, and the weights,
    ``exp((l - l_max) / ogain)``, are flatter for a larger ``ogain``. The weighted covariance
    of those poses is :meth:`~belvedere.nav.slam.SubmapSlam.covariance`, and its entropy is
    what the node publishes on ``~entropy``. They do not change the trajectory or the map.
    An axis sampled once (range 0, or under its step) takes the match's least-squares
    variance instead. The steps must be positive and the ranges not negative.
``particles``, ``resampleThreshold``
    The particle filter's: how many trajectories, and when to resample them. One trajectory
    in a pose graph takes their place here, so they have no effect: setting them draws one
    warning (:meth:`GMappingParams.without_effect`).
"""

from __future__ import annotations

import builtins
import dataclasses
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from belvedere.bounded import GRID_CELLS

__all__ = ["GMappingParams"]

_WITHOUT_EFFECT = (
    (
        ("particles", "resampleThreshold"),
        "belvedere's mapper keeps one trajectory in a pose graph, not a particle filter",
    ),
    (("seed",), "the mapper is deterministic and draws no random numbers"),
)
"""Parameters read and checked that change nothing, and why."""


@dataclass(frozen=True)
class GMappingParams:
    """slam_gmapping's parameters and defaults (``maxRange``/``maxUrange`` ``None``: from
    the first scan)."""

    maxRange: float | None = None  # noqa: N815 - ROS parameter names
    maxUrange: float | None = None  # noqa: N815
    sigma: float = 0.05
    kernelSize: int = 1  # noqa: N815
    lstep: float = 0.05
    astep: float = 0.05
    iterations: int = 5
    lsigma: float = 0.075
    ogain: float = 3.0
    lskip: int = 0
    minimumScore: float = 0.0  # noqa: N815
    srr: float = 0.1
    srt: float = 0.2
    str: float = 0.1
    stt: float = 0.2
    linearUpdate: float = 1.0  # noqa: N815
    angularUpdate: float = 0.5  # noqa: N815
    temporalUpdate: float = -1.0  # noqa: N815
    resampleThreshold: float = 0.5  # noqa: N815
    particles: int = 30
    xmin: float = -100.0
    ymin: float = -100.0
    xmax: float = 100.0
    ymax: float = 100.0
    delta: float = 0.05
    llsamplerange: float = 0.01
    llsamplestep: float = 0.01
    lasamplerange: float = 0.005
    lasamplestep: float = 0.005
    occ_thresh: float = 0.25
    map_update_interval: float = 5.0
    throttle_scans: int = 1
    seed: int = 0
    """Not a slam_gmapping parameter (it seeds from the clock): the mapper is deterministic
    and draws no random numbers; kept so that runs name their seed (with a warning that it
    has no effect)."""

    @classmethod
    def names(cls) -> tuple[builtins.str, ...]:
        return tuple(f.name for f in dataclasses.fields(cls))

    @classmethod
    def without_effect(cls, given: Iterable[builtins.str]) -> builtins.str | None:
        """What to warn of when the parameters ``given`` (names) include some that have no
        effect here: one sentence naming them and why, or None."""
        given = set(given)
        parts = []
        for names, why in _WITHOUT_EFFECT:
            named = [name for name in names if name in given]
            if named:
                verb = "has" if len(named) == 1 else "have"
                parts.append(f"{', '.join(named)} {verb} no effect here: {why}")
        return "; ".join(parts) or None

    @classmethod
    def from_mapping(cls, values: Mapping[builtins.str, Any]) -> GMappingParams:
        """Parameters from ``name → value`` (unknown names are the caller's business), each
        converted to its field's type; a wrong value raises ``ValueError`` naming it."""
        fields = {f.name: f for f in dataclasses.fields(cls)}
        kwargs: dict[str, Any] = {}
        for name, raw in values.items():
            if name not in fields:
                continue
            kind = fields[name].type
            try:
                if kind in ("int", int):
                    if isinstance(raw, bool) or (isinstance(raw, float) and not raw.is_integer()):
                        raise ValueError
                    value: Any = int(raw)
                else:
                    if isinstance(raw, bool):
                        raise ValueError
                    value = float(raw)
                    if not math.isfinite(value):
                        raise ValueError
            except (TypeError, ValueError):
                whole = "whole " if kind in ("int", int) else ""
                message = f"parameter {name}: expected a {whole}number, got {raw!r}"
                raise ValueError(message) from None
            kwargs[name] = value
        params = cls(**kwargs)
        params.check()
        return params

    def check(self) -> None:
        """Raise ``ValueError`` for values the mapper cannot work with."""
        positive = {
            "delta": self.delta,
            "sigma": self.sigma,
            "lstep": self.lstep,
            "astep": self.astep,
            "lsigma": self.lsigma,
            "ogain": self.ogain,
            "llsamplestep": self.llsamplestep,
            "lasamplestep": self.lasamplestep,
        }
        for name, value in positive.items():
            if value <= 0:
                message = f"parameter {name} must be positive, got {value}"
                raise ValueError(message)
        for name in ("kernelSize", "lskip", "iterations", "llsamplerange", "lasamplerange"):
            if getattr(self, name) < 0:
                message = f"parameter {name} must not be negative, got {getattr(self, name)}"
                raise ValueError(message)
        if self.throttle_scans < 1:
            message = f"parameter throttle_scans must be at least 1, got {self.throttle_scans}"
            raise ValueError(message)
        if self.particles < 1:
            message = f"parameter particles must be at least 1, got {self.particles}"
            raise ValueError(message)
        if self.xmax <= self.xmin or self.ymax <= self.ymin:
            message = "parameters xmin/xmax, ymin/ymax: the map's extent is empty"
            raise ValueError(message)
        cells = math.ceil((self.xmax - self.xmin) / self.delta) * math.ceil(
            (self.ymax - self.ymin) / self.delta
        )
        if cells > GRID_CELLS:
            message = (
                f"parameters xmin/xmax, ymin/ymax, delta: a map of {cells:,} cells, more than "
                f"the cap of {GRID_CELLS:,}"
            )
            raise ValueError(message)
