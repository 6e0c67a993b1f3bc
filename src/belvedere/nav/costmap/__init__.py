"""costmap_2d over plain arrays: the cost grid planners read."""

from belvedere.nav.costmap._grid import FREE, INSCRIBED, LETHAL, NO_INFORMATION, CostGrid

__all__ = ["FREE", "INSCRIBED", "LETHAL", "NO_INFORMATION", "CostGrid"]
