"""slam_gmapping's parameters, with its names and defaults, and what each does here.

The mapper (:class:`belvedere.nav.slam.SubmapSlam`) is not GMapping's particle filter but
reads the same parameters, each with the same intent:

``maxRange``
    Beams longer than this are dropped altogether (no return). Default: the scan's
    ``range_max`` − 0.01 m, as slam_gmapping sets it from the first scan.
``maxUrange``
    Beams are used for matching and mapping up to this range; longer ones (up to
    ``maxRange``) only clear the cells along them. Default: ``maxRange``.
``sigma``, ``kernelSize``
    The matcher's likelihood field: a Gaussian of standard deviation
    ``sqrt(sigma / 2)`` metres — GMapping scores ``exp(-d²/sigma)`` — around every end point,
    cut ``kernelSize + 2`` cells away.
``lstep``, ``astep``, ``iterations``
    When a match scores below ``minimumScore``, the pose is searched (branch and bound) within
    ``±iterations·lstep`` metres and ``±iterations·astep`` radians of the prediction before
    it is refined again; ``2·iterations`` bounds the Levenberg-Marquardt iterations of every
    match.
``lsigma``, ``ogain``
    Loop closures: a candidate's likelihood is ``exp(-ogain · (1 − score)² / (2 lsigma²))``
    per beam (GMapping smooths the particle weights the same way); closures whose
    likelihood falls under the gaussian's 3σ point are rejected.
``lskip``
    Take every (lskip+1)-th beam for matching.
``minimumScore``
    GMapping's score is a sum over beams; here the mean field value per beam is multiplied by
    the number of matched beams to compare with it. A match below it falls back to a lattice
    search (and then to odometry). 0 accepts every match.
``srr``, ``srt``, ``str``, ``stt``
    The odometry error model (translation from translation, translation from rotation,
    rotation from translation, rotation from rotation): the standard deviations of the
    motion prior each match is pulled towards, and of the submap chain in the pose graph.
``linearUpdate``, ``angularUpdate``, ``temporalUpdate``
    A scan is added to the map (a keyframe) after the robot travelled ``linearUpdate`` m,
    turned ``angularUpdate`` rad, or ``temporalUpdate`` s passed (if ≥ 0) since the last one.
    Every scan is still matched, so the trajectory has one pose per scan.
``particles``, ``resampleThreshold``
    The number of hypotheses and when to resample. This mapper keeps one trajectory and
    closes loops by optimising a pose graph instead, so it reads them and ignores them.
``xmin``, ``ymin``, ``xmax``, ``ymax``, ``delta``
    The map's initial extent (it grows to fit) and its resolution; ``delta`` is also the
    resolution of the grids matched against.
``llsamplerange``, ``llsamplestep``, ``lasamplerange``, ``lasamplestep``
    GMapping samples the likelihood around the matched pose to estimate its covariance; here
    the matcher's Hessian gives that covariance, the ranges floor its standard deviations.
``occ_thresh``, ``map_update_interval``, ``throttle_scans``
    The node's: cells with hit/visit ratio above ``occ_thresh`` are occupied; the map is
    rebuilt every ``map_update_interval`` s; only every ``throttle_scans``-th scan is used.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

__all__ = ["GMappingParams"]


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
    and draws no random numbers; kept so that runs name their seed."""

    @classmethod
    def names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in dataclasses.fields(cls))

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> GMappingParams:
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
                message = f"parameter {name}: expected a {'whole ' if kind in ('int', int) else ''}number, got {raw!r}"
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
        }
        for name, value in positive.items():
            if value <= 0:
                message = f"parameter {name} must be positive, got {value}"
                raise ValueError(message)
        for name in ("kernelSize", "lskip", "iterations"):
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
