"""costmap_2d over plain arrays: the cost grid planners read, and the layers that make it
(static, obstacle, inflation) with both parameter styles (pre-Hydro and ``plugins``)."""

from belvedere.nav.costmap._footprint import (
    circle_footprint,
    footprint_from_params,
    pad_footprint,
    radii,
)
from belvedere.nav.costmap._grid import FREE, INSCRIBED, LETHAL, NO_INFORMATION, CostGrid
from belvedere.nav.costmap._layered import Layer, LayeredCostmap
from belvedere.nav.costmap._layers import (
    InflationLayer,
    Observation,
    ObstacleLayer,
    StaticLayer,
    inflation_cost,
)
from belvedere.nav.costmap._params import (
    LAYER_TYPES,
    CostmapParams,
    InflationParams,
    LayerParams,
    ObstacleParams,
    SourceParams,
    StaticParams,
)
from belvedere.nav.costmap._raster import convex_fill, raytrace

__all__ = [
    "FREE",
    "INSCRIBED",
    "LAYER_TYPES",
    "LETHAL",
    "NO_INFORMATION",
    "CostGrid",
    "CostmapParams",
    "InflationLayer",
    "InflationParams",
    "Layer",
    "LayerParams",
    "LayeredCostmap",
    "Observation",
    "ObstacleLayer",
    "ObstacleParams",
    "SourceParams",
    "StaticLayer",
    "StaticParams",
    "circle_footprint",
    "convex_fill",
    "footprint_from_params",
    "inflation_cost",
    "pad_footprint",
    "radii",
    "raytrace",
]
