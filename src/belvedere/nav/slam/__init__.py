"""2D laser SLAM: slam_gmapping's inputs and parameters over a submap and pose-graph mapper
(:class:`SubmapSlam`), and hector_mapping's scan matcher over a multi-resolution grid
(:class:`HectorSlam`)."""

from belvedere.nav.slam._hector import HectorParams, HectorSlam, LogOddsGrid
from belvedere.nav.slam._params import GMappingParams
from belvedere.nav.slam._slam import LaserGeometry, ScanPose, SubmapSlam, Tuning

__all__ = [
    "GMappingParams",
    "HectorParams",
    "HectorSlam",
    "LaserGeometry",
    "LogOddsGrid",
    "ScanPose",
    "SubmapSlam",
    "Tuning",
]
