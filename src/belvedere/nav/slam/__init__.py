"""2D laser SLAM: slam_gmapping's inputs and parameters over a submap and pose-graph mapper
(:class:`SubmapSlam`)."""

from belvedere.nav.slam._occupancy import OccupancyMap
from belvedere.nav.slam._params import GMappingParams
from belvedere.nav.slam._slam import LaserGeometry, ScanPose, SubmapSlam, Tuning

__all__ = ["GMappingParams", "LaserGeometry", "OccupancyMap", "ScanPose", "SubmapSlam", "Tuning"]
