"""The submap mapper's data: the laser's geometry and tuning, what a scan gives back, and what
the mapper keeps per submap, keyframe, loop closure and scan (see :mod:`._slam`)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from belvedere.bounded import SCAN_BEAMS
from belvedere.nav.slam._grid import FieldGrid, FreeGrid
from belvedere.nav.slam._search import SearchPyramid

__all__ = ["LaserGeometry", "ScanPose", "Tuning"]

Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class LaserGeometry:
    """Where the beams point, in the base frame (the laser assumed level)."""

    directions: Array
    """(B, 2) unit vectors, one per beam in the scan's order."""
    origin: Array
    """(2,) the laser's position on the base."""
    range_min: float
    range_max: float

    @classmethod
    def planar(
        cls,
        angle_min: float,
        angle_increment: float,
        count: int,
        range_min: float,
        range_max: float,
        laser_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
        upside_down: bool = False,
    ) -> LaserGeometry:
        """Beams of a ``LaserScan`` from a laser at ``laser_pose`` (x, y, yaw) on the base;
        ``upside_down`` mirrors them (a laser mounted with its z axis down)."""
        angles = angle_min + np.arange(count) * angle_increment
        if upside_down:
            angles = -angles
        yaw = laser_pose[2]
        directions = np.stack([np.cos(angles + yaw), np.sin(angles + yaw)], axis=1)
        return cls(
            directions=directions,
            origin=np.array(laser_pose[:2], dtype=np.float64),
            range_min=float(range_min),
            range_max=float(range_max),
        )

    def problem(self) -> str | None:
        """Why the mapper cannot use these beams, or None: more than
        :data:`~belvedere.bounded.SCAN_BEAMS`, a direction or the origin not finite, a range
        limit NaN."""
        count = len(self.directions)
        if count > SCAN_BEAMS:
            return f"the laser has {count:,} beams, more than the cap of {SCAN_BEAMS:,}"
        if not (np.isfinite(self.directions).all() and np.isfinite(self.origin).all()):
            return "the laser's beam directions or position are not finite"
        if math.isnan(self.range_min) or math.isnan(self.range_max):
            return "the laser's range_min or range_max is nan"
        return None

    def checked(self) -> LaserGeometry:
        """These beams, with a negative ``range_min`` raised to 0 (a negative range is no
        reading, whatever the scan says: -inf would end no beam).

        Raises:
            ValueError: :meth:`problem`.
        """
        problem = self.problem()
        if problem is not None:
            raise ValueError(problem)
        return self if self.range_min >= 0 else dataclasses.replace(self, range_min=0.0)


@dataclass(frozen=True)
class Tuning:
    """Constants of this mapper that GMapping has no parameter for."""

    submap_keyframes: int = 20
    field_sigma: float | None = None
    """Standard deviation (m) of the likelihood field; None: from ``sigma``."""
    field_radius: int | None = None
    """Kernel radius in cells; None: from ``kernelSize``."""
    field_saturation: float = 1.5
    """End points in a cell for its full weight. A wall seen once weighs 1/this: the part
    of a wall only the last keyframe saw is a lower ridge, whose slope drags the next scans
    back along the wall (towards the parts seen more often)."""
    prior_floor_xy: float = 0.02
    prior_floor_theta: float = 0.05
    """The odometry prior's least standard deviation per scan (m, rad): loose enough that
    a match seeing little (a short ``maxUrange``) is not pulled along with the odometry's
    heading creep."""
    loop_radius: float = 4.0
    """Finished submaps with a keyframe this near (m) are searched for loop closures."""
    loop_min_score: float = 0.45
    loop_window_xy: tuple[float, float, float] = (0.3, 0.08, 5.0)
    """Linear window: base (m), growth per metre travelled since the last closure, cap."""
    loop_window_theta: tuple[float, float, float] = (0.05, 0.0035, 0.35)
    loop_max_range: float = 20.0
    """Beams used to search for closures are cut to this range (m) (finer angular steps
    would otherwise be needed)."""
    loop_points: int = 90
    loop_sigma_xy: float = 0.05
    loop_sigma_theta: float = 0.01
    loop_huber: float = 3.0
    """Loop edges cost linearly beyond this Mahalanobis distance when the graph is
    optimised (a Huber kernel, as Cartographer's): a wrong closure that got this far pulls
    the graph with a bounded force, too weak to bend it, and is then dropped by
    ``loop_max_error``."""
    loop_min_travel: float = 15.0
    """Submaps nearer than this along the graph (m) are not searched for closures."""
    loop_min_ratio: float = 0.1
    """Closures whose translational information is this lopsided (corridors) are dropped."""
    loop_max_chi2: float = 100.0
    """Closures adding more than this to the graph's χ² (after optimising) are refused:
    their correction lies that far (squared, Mahalanobis) outside the drift the chain
    edges allow between their ends."""
    loop_max_error: float = 8.0
    """After optimising, a new closure this far (Mahalanobis) from the graph is dropped."""
    loop_max_contradiction: float = 0.2
    """A closure whose end points fall in the submap's free space more than this share of
    those the submap knows about is dropped."""
    free_cells: int = 4
    """The free-space grid's cells, in map cells."""
    covered_min: float = 0.5
    """The scan is matched with its points inside the submap's mapped range only, unless
    fewer than this share of them are."""
    free_short: float = 0.4
    """Beams count as passing up to this far (m) before their end."""
    loop_ambiguity: float = 0.9
    """A closure whose scan fits another pose in the window nearly as well (this fraction of
    the best score) is dropped. At 0.8, a short-range scan in a corridor (its two long walls
    most of its points) always had a second peak half a metre along and no closure was made;
    the contradiction check, the graph's error and its χ² gate stand behind this one."""
    agree_xy: float = 0.1
    agree_theta: float = 0.01
    """A closure moving its keyframe less than this agrees with the graph: accepted."""
    consistent_xy: float = 0.25
    consistent_theta: float = 0.025
    consistent_rate: float = 0.1
    """Two closures asking for corrections this close confirm each other (the linear part
    grows by this fraction of the correction asked for)."""
    pending_travel: float = 30.0
    """How long (metres travelled) a closure waits for confirmation."""
    loop_length: float = 1.0
    """A loop edge's length for the search windows (metres of travel it stands for)."""
    chain_sigma_xy: tuple[float, float] = (0.01, 0.01)
    """Submap chain edge: base (m), growth per metre."""
    chain_sigma_theta: tuple[float, float] = (0.002, 0.002)
    search_depth: int = 6
    optimize_error: float = 2.0
    """New loop edges this far (Mahalanobis) from the graph's estimate: optimise at once."""
    optimize_every: int = 10
    """Otherwise optimise after this many new loop edges."""
    optimize_iterations: int = 4


@dataclass(frozen=True)
class ScanPose:
    """The result of one scan: the base's pose in the map frame, whether the scan was added
    to the map (a keyframe), and the match's quality."""

    pose: Array
    keyframe: bool
    score: float


@dataclass
class _Submap:
    grid: FieldGrid
    anchor: tuple[int, Array] | None
    """(submap, pose in it) this one was created at."""
    keyframes: int = 0
    pyramid: SearchPyramid | None = None
    finished: bool = False
    free: FreeGrid | None = None
    """Where the submap's keyframes' beams passed (coarse)."""
    sensors: Array = field(default_factory=lambda: np.zeros((0, 2)))
    """Where the laser was (submap frame) for each keyframe inserted."""


@dataclass
class _Keyframe:
    stamp: float
    ranges: npt.NDArray[np.float32]
    home: int
    local: Array
    search: Array
    """The (subsampled, range-limited) points used to search for loop closures."""
    other: int = -1
    weight: float = 0.0
    travel: float = 0.0
    """Metres travelled (by odometry) when it was taken."""
    extent: float = 0.0
    """How far from the base its traced beams reach (m): the map it draws into lies within
    this of its pose."""


@dataclass(eq=False)
class _Closure:
    keyframe: int
    submap: int
    measurement: Array
    """The keyframe's home submap seen from ``submap``."""
    information: Array
    """Of the keyframe's pose in ``submap`` (its own frame's axes)."""


@dataclass
class _LastMatch:
    """What the pose's covariance is computed from when it is asked for (not before: a run
    that never asks pays nothing for it)."""

    submap: int
    version: int
    """The submap's grid's :attr:`~FieldGrid.version` the scan was matched against."""
    pose: Array
    """The match, in the submap's frame."""
    points: Array
    """The end points matched (the base's frame)."""
    information: Array
    variance: float
    """The match's least-squares information and its residuals' variance."""
    covariance: Array | None = None
    """Once computed (the submap's frame)."""


@dataclass
class _State:
    scans_stamp: list[float] = field(default_factory=list)
    scans_home: list[int] = field(default_factory=list)
    scans_local: list[Array] = field(default_factory=list)
    scans_other: list[int] = field(default_factory=list)
    scans_weight: list[float] = field(default_factory=list)
