"""Occupancy maps in map_server's files: reading a map's YAML and image as map_server 1.x
does, writing ``NAME.pgm`` + ``NAME.yaml`` byte for byte as map_saver does, the maps as
``nav_msgs`` messages, pictures of maps, and TUM trajectories.

Example::

    from belvedere.maps import load_map, save_map
    grid = load_map("maps/cloister.yaml")   # OccupancyMap: data[row, col], row 0 at the bottom
    save_map("copy", grid)                  # copy.pgm, copy.yaml as `map_saver -f copy`
"""

from belvedere.maps._image import ImageError, MapImage, read_map_image
from belvedere.maps._load import (
    DEFAULT_FREE_THRESH,
    DEFAULT_OCCUPIED_THRESH,
    MODES,
    MapMode,
    MapYaml,
    load_image_map,
    load_map,
    occupancy_from_pixels,
    read_map_yaml,
)
from belvedere.maps._message import grid_message, map_from_message, metadata_message
from belvedere.maps._model import (
    FREE,
    OCCUPIED,
    UNKNOWN,
    MapError,
    OccupancyMap,
    quat_xyzw_from_yaw,
    yaw_from_quat_xyzw,
)
from belvedere.maps._render import map_picture, map_summary
from belvedere.maps._save import (
    DEFAULT_SAVE_FREE,
    DEFAULT_SAVE_OCCUPIED,
    map_pgm_bytes,
    map_yaml_text,
    save_map,
)
from belvedere.maps._tum import TrajectoryError, format_tum_line, read_tum

__all__ = [
    "DEFAULT_FREE_THRESH",
    "DEFAULT_OCCUPIED_THRESH",
    "DEFAULT_SAVE_FREE",
    "DEFAULT_SAVE_OCCUPIED",
    "FREE",
    "MODES",
    "OCCUPIED",
    "UNKNOWN",
    "ImageError",
    "MapError",
    "MapImage",
    "MapMode",
    "MapYaml",
    "OccupancyMap",
    "TrajectoryError",
    "format_tum_line",
    "grid_message",
    "load_image_map",
    "load_map",
    "map_from_message",
    "map_pgm_bytes",
    "map_picture",
    "map_summary",
    "map_yaml_text",
    "metadata_message",
    "occupancy_from_pixels",
    "quat_xyzw_from_yaw",
    "read_map_image",
    "read_map_yaml",
    "read_tum",
    "save_map",
    "yaw_from_quat_xyzw",
]
