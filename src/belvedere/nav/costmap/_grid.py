"""The cost grid that costmaps produce and planners read: costmap_2d's cell costs over a grid.

Cell (row j, column i) covers ``origin + [i, i+1)·res x [j, j+1)·res`` in the costmap's global
frame, as a ``nav_msgs/OccupancyGrid`` lays its data out (row-major from the lower-left corner).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
import numpy.typing as npt

__all__ = [
    "FREE",
    "INSCRIBED",
    "LETHAL",
    "NO_INFORMATION",
    "CostGrid",
]

FREE: Final = 0
INSCRIBED: Final = 253
"""The robot's centre here puts part of its footprint in an obstacle (inscribed radius)."""
LETHAL: Final = 254
NO_INFORMATION: Final = 255

Costs = npt.NDArray[np.uint8]


@dataclass
class CostGrid:
    """Costs 0-255 as costmap_2d keeps them; ``costs[j, i]`` is the cell at column i, row j."""

    costs: Costs
    resolution: float
    origin_x: float = 0.0
    origin_y: float = 0.0

    @property
    def width(self) -> int:
        return int(self.costs.shape[1])

    @property
    def height(self) -> int:
        return int(self.costs.shape[0])

    def world_to_map(self, x: float, y: float) -> tuple[int, int] | None:
        """The (column, row) holding the point, or None outside the grid."""
        i = math.floor((x - self.origin_x) / self.resolution)
        j = math.floor((y - self.origin_y) / self.resolution)
        if 0 <= i < self.width and 0 <= j < self.height:
            return i, j
        return None

    def map_to_world(self, i: float, j: float) -> tuple[float, float]:
        """The centre of cell (column i, row j)."""
        return (
            self.origin_x + (i + 0.5) * self.resolution,
            self.origin_y + (j + 0.5) * self.resolution,
        )
