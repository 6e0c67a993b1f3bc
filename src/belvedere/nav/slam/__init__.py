"""2D laser SLAM: hector_mapping's scan matcher over a multi-resolution grid."""

from belvedere.nav.slam._hector import HectorParams, HectorSlam, LogOddsGrid

__all__ = ["HectorParams", "HectorSlam", "LogOddsGrid"]
