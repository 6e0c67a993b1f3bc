"""costmap_2d's parameters, in both styles the course uses, read into one layer list.

Pre-Hydro (no ``plugins``): ``static_map: true`` adds a ``static_layer`` (with ``map_topic``,
``unknown_cost_value``, ``lethal_cost_threshold``, ``track_unknown_space`` from the costmap's
namespace), then always an ``obstacle_layer`` (``map_type: voxel`` or ``costmap``; with
``max_obstacle_height``, ``obstacle_range``, ``raytrace_range``, ``track_unknown_space``,
``observation_sources`` and each source's namespace) and an ``inflation_layer``
(``inflation_radius``, ``cost_scaling_factor``) — what ``Costmap2DROS::loadOldParameters``
moves. Layered: ``plugins`` lists ``{name, type}``; each layer reads its own namespace, and the
costmap's values of the parameters above are copied into the layers (costmap_2d's
``copyParentParameters``, which overwrites a layer's own value). A source's
``obstacle_range``/``raytrace_range`` are searched from the source's namespace outward, as
``searchParam`` does.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
import numpy.typing as npt

from belvedere.bounded import GRID_CELLS
from belvedere.nav.costmap._footprint import footprint_from_params, pad_footprint

__all__ = [
    "LAYER_TYPES",
    "CostmapParams",
    "InflationParams",
    "LayerParams",
    "ObstacleParams",
    "SourceParams",
    "StaticParams",
]

STATIC: Final = "costmap_2d::StaticLayer"
OBSTACLE: Final = "costmap_2d::ObstacleLayer"
VOXEL: Final = "costmap_2d::VoxelLayer"
INFLATION: Final = "costmap_2d::InflationLayer"
LAYER_TYPES: Final = (STATIC, OBSTACLE, VOXEL, INFLATION)

_PARENT_COPIES: Final = {
    STATIC: ("map_topic", "unknown_cost_value", "lethal_cost_threshold", "track_unknown_space"),
    OBSTACLE: ("max_obstacle_height", "raytrace_range", "obstacle_range", "track_unknown_space"),
    VOXEL: ("max_obstacle_height", "raytrace_range", "obstacle_range", "track_unknown_space"),
    INFLATION: ("cost_scaling_factor", "inflation_radius"),
}
"""What a layer takes from the costmap's namespace when it does not set it."""

_DATA_TYPES: Final = ("LaserScan", "PointCloud", "PointCloud2")


class _Reader:
    """Typed reads from one namespace; errors name the parameter by its path."""

    def __init__(self, values: Mapping[str, Any], path: str) -> None:
        self.values = values
        self.path = path

    def name(self, key: str) -> str:
        return f"{self.path}/{key}" if self.path else key

    def number(self, key: str, default: float) -> float:
        value = self.values.get(key, default)
        if isinstance(value, bool) or not isinstance(value, int | float):
            message = f"parameter {self.name(key)!r} must be a number, not {value!r}"
            raise ValueError(message)
        return float(value)

    def positive(self, key: str, default: float) -> float:
        value = self.number(key, default)
        if value <= 0:
            message = f"parameter {self.name(key)!r} must be positive, not {value!r}"
            raise ValueError(message)
        return value

    def integer(self, key: str, default: int) -> int:
        value = self.values.get(key, default)
        if isinstance(value, bool) or not isinstance(value, int):
            message = f"parameter {self.name(key)!r} must be an integer, not {value!r}"
            raise ValueError(message)
        return value

    def flag(self, key: str, default: bool) -> bool:
        value = self.values.get(key, default)
        if not isinstance(value, bool):
            message = f"parameter {self.name(key)!r} must be true or false, not {value!r}"
            raise ValueError(message)
        return value

    def text(self, key: str, default: str) -> str:
        value = self.values.get(key, default)
        if not isinstance(value, str):
            message = f"parameter {self.name(key)!r} must be a string, not {value!r}"
            raise ValueError(message)
        return value

    def namespace(self, key: str) -> _Reader:
        value = self.values.get(key)
        if not isinstance(value, Mapping):
            what = "missing" if value is None else f"{value!r}"
            message = f"parameter {self.name(key)!r} must be a namespace of parameters, not {what}"
            raise ValueError(message)
        return _Reader(value, self.name(key))


@dataclass(frozen=True)
class SourceParams:
    """One observation source of an obstacle layer."""

    name: str
    topic: str
    sensor_frame: str
    data_type: str
    observation_persistence: float
    expected_update_rate: float
    min_obstacle_height: float
    max_obstacle_height: float
    obstacle_range: float
    raytrace_range: float
    marking: bool
    clearing: bool
    inf_is_valid: bool


@dataclass(frozen=True)
class StaticParams:
    name: str
    map_topic: str = "map"
    unknown_cost_value: int = -1
    lethal_cost_threshold: int = 100
    track_unknown_space: bool = True
    trinary_costmap: bool = True
    use_maximum: bool = False
    first_map_only: bool = False
    subscribe_to_updates: bool = False
    enabled: bool = True


@dataclass(frozen=True)
class ObstacleParams:
    """An obstacle layer. ``voxel`` marks a ``costmap_2d::VoxelLayer``, run here as the 2D
    obstacle layer (its column of voxels projected: marks from points between the height
    limits, clearing by 2D ray tracing; ``z_voxels``/``mark_threshold`` are not modelled)."""

    name: str
    voxel: bool
    track_unknown_space: bool
    max_obstacle_height: float = 2.0
    combination_method: int = 1
    footprint_clearing_enabled: bool = True
    sources: tuple[SourceParams, ...] = ()
    enabled: bool = True


@dataclass(frozen=True)
class InflationParams:
    name: str
    inflation_radius: float = 0.55
    cost_scaling_factor: float = 10.0
    inflate_unknown: bool = False
    enabled: bool = True


LayerParams = StaticParams | ObstacleParams | InflationParams


def _sources(reader: _Reader, outer: Sequence[Mapping[str, Any]]) -> tuple[SourceParams, ...]:
    names = reader.text("observation_sources", "").split()
    sources = []
    for name in names:
        ns = reader.namespace(name)
        data_type = ns.text("data_type", "PointCloud")
        if data_type not in _DATA_TYPES:
            message = (
                f"parameter {ns.name('data_type')!r} must be one of {', '.join(_DATA_TYPES)}, "
                f"not {data_type!r}"
            )
            raise ValueError(message)
        ranges = {}
        for key, default in (("obstacle_range", 2.5), ("raytrace_range", 3.0)):
            value: float = default
            for scope in (ns.values, reader.values, *outer):
                if key in scope:
                    value = _Reader(scope, ns.path).number(key, default)
                    break
            ranges[key] = value
        sources.append(
            SourceParams(
                name=name,
                topic=ns.text("topic", name),
                sensor_frame=ns.text("sensor_frame", "").lstrip("/"),
                data_type=data_type,
                observation_persistence=ns.number("observation_persistence", 0.0),
                expected_update_rate=ns.number("expected_update_rate", 0.0),
                min_obstacle_height=ns.number("min_obstacle_height", 0.0),
                max_obstacle_height=ns.number("max_obstacle_height", 2.0),
                obstacle_range=ranges["obstacle_range"],
                raytrace_range=ranges["raytrace_range"],
                marking=ns.flag("marking", True),
                clearing=ns.flag("clearing", False),
                inf_is_valid=ns.flag("inf_is_valid", False),
            )
        )
    return tuple(sources)


def _layer(
    name: str,
    kind: str,
    reader: _Reader,
    master_unknown: bool,
    outer: Sequence[Mapping[str, Any]],
) -> LayerParams:
    if kind == STATIC:
        return StaticParams(
            name=name,
            map_topic=reader.text("map_topic", "map"),
            unknown_cost_value=reader.integer("unknown_cost_value", -1),
            lethal_cost_threshold=reader.integer("lethal_cost_threshold", 100),
            track_unknown_space=reader.flag("track_unknown_space", True),
            trinary_costmap=reader.flag("trinary_costmap", True),
            use_maximum=reader.flag("use_maximum", False),
            first_map_only=reader.flag("first_map_only", False),
            subscribe_to_updates=reader.flag("subscribe_to_updates", False),
            enabled=reader.flag("enabled", True),
        )
    if kind in (OBSTACLE, VOXEL):
        method = reader.integer("combination_method", 1)
        if method not in (0, 1):
            message = (
                f"parameter {reader.name('combination_method')!r} must be 0 (overwrite) or "
                f"1 (maximum), not {method}"
            )
            raise ValueError(message)
        return ObstacleParams(
            name=name,
            voxel=kind == VOXEL,
            track_unknown_space=reader.flag("track_unknown_space", master_unknown),
            max_obstacle_height=reader.number("max_obstacle_height", 2.0),
            combination_method=method,
            footprint_clearing_enabled=reader.flag("footprint_clearing_enabled", True),
            sources=_sources(reader, outer),
            enabled=reader.flag("enabled", True),
        )
    radius = reader.number("inflation_radius", 0.55)
    if radius < 0:
        message = (
            f"parameter {reader.name('inflation_radius')!r} must not be negative, not {radius}"
        )
        raise ValueError(message)
    return InflationParams(
        name=name,
        inflation_radius=radius,
        cost_scaling_factor=reader.number("cost_scaling_factor", 10.0),
        inflate_unknown=reader.flag("inflate_unknown", False),
        enabled=reader.flag("enabled", True),
    )


def _copy_parent(ns: Mapping[str, Any], costmap: Mapping[str, Any], kind: str) -> dict[str, Any]:
    merged = dict(ns)
    for key in _PARENT_COPIES[kind]:
        if key in costmap:  # copyParentParameters overwrites the layer's own value
            merged[key] = costmap[key]
    return merged


def _pre_hydro(values: Mapping[str, Any]) -> list[tuple[str, str, dict[str, Any]]]:
    """The layers ``loadOldParameters`` makes, each with the namespace it would read."""
    layers: list[tuple[str, str, dict[str, Any]]] = []
    root = _Reader(values, "")
    if root.flag("static_map", False):
        layers.append(
            ("static_layer", STATIC, _copy_parent(values.get("static_layer", {}), values, STATIC))
        )
    map_type = root.text("map_type", "costmap")
    if map_type not in ("costmap", "voxel"):
        message = f"parameter 'map_type' must be 'costmap' or 'voxel', not {map_type!r}"
        raise ValueError(message)
    obstacles = dict(values.get("obstacle_layer", {}))
    for key in (*_PARENT_COPIES[OBSTACLE], "observation_sources"):
        if key in values:
            obstacles[key] = values[key]
    for source in root.text("observation_sources", "").split():
        if source in values:
            obstacles[source] = values[source]
    layers.append(("obstacle_layer", VOXEL if map_type == "voxel" else OBSTACLE, obstacles))
    inflation = _copy_parent(values.get("inflation_layer", {}), values, INFLATION)
    layers.append(("inflation_layer", INFLATION, inflation))
    return layers


def _plugins(values: Mapping[str, Any]) -> list[tuple[str, str, dict[str, Any]]]:
    plugins = values["plugins"]
    if not isinstance(plugins, list):
        message = f"parameter 'plugins' must be a list of {{name, type}}, not {plugins!r}"
        raise ValueError(message)
    layers = []
    for index, entry in enumerate(plugins):
        if (
            not isinstance(entry, Mapping)
            or not isinstance(entry.get("name"), str)
            or not isinstance(entry.get("type"), str)
        ):
            message = (
                f"parameter 'plugins' item {index} must be {{name: ..., type: ...}}, not {entry!r}"
            )
            raise ValueError(message)
        name, kind = entry["name"], entry["type"]
        if kind not in LAYER_TYPES:
            message = (
                f"parameter 'plugins' item {index} ({name}): unknown layer type {kind!r} "
                f"(supported: {', '.join(LAYER_TYPES)})"
            )
            raise ValueError(message)
        ns = values.get(name, {})
        if not isinstance(ns, Mapping):
            message = f"parameter {name!r} must be a namespace of parameters, not {ns!r}"
            raise ValueError(message)
        layers.append((name, kind, _copy_parent(ns, values, kind)))
    return layers


@dataclass(frozen=True)
class CostmapParams:
    """One costmap's parameters (its ``~<name>/`` namespace), with its layers in order."""

    global_frame: str
    robot_base_frame: str
    transform_tolerance: float
    update_frequency: float
    publish_frequency: float
    rolling_window: bool
    track_unknown_space: bool
    always_send_full_costmap: bool
    width: float
    height: float
    resolution: float
    origin_x: float
    origin_y: float
    footprint: npt.NDArray[np.float64]
    """The padded footprint (K, 2) in the robot's frame."""
    footprint_padding: float
    layers: tuple[LayerParams, ...]
    pre_hydro: bool

    @classmethod
    def from_mapping(
        cls, values: Mapping[str, Any], *, outer: Sequence[Mapping[str, Any]] = ()
    ) -> CostmapParams:
        """From the costmap's namespace as a nested mapping; ``outer`` are the enclosing
        namespaces (innermost first) that ``searchParam`` would look in.

        Raises:
            ValueError: a bad parameter (the message names it).
        """
        root = _Reader(values, "")
        track_unknown = root.flag("track_unknown_space", False)
        pre_hydro = "plugins" not in values
        specs = _pre_hydro(values) if pre_hydro else _plugins(values)
        # pre-Hydro parameters sit in the costmap's namespace: errors name them there
        layers = tuple(
            _layer(
                name, kind, _Reader(ns, "" if pre_hydro else name), track_unknown, [values, *outer]
            )
            for name, kind, ns in specs
        )
        padding = root.number("footprint_padding", 0.01)
        unpadded = footprint_from_params(values.get("footprint"), values.get("robot_radius", 0.46))
        width, height = root.positive("width", 10), root.positive("height", 10)
        resolution = root.positive("resolution", 0.05)
        cells = float(np.floor(width / resolution) * np.floor(height / resolution))
        if not cells <= GRID_CELLS:  # (NaN and inf too)
            message = (
                f"parameters width, height, resolution: a costmap of {cells:,.0f} cells, more "
                f"than the cap of {GRID_CELLS:,}"
            )
            raise ValueError(message)
        return cls(
            global_frame=root.text("global_frame", "map").lstrip("/"),
            robot_base_frame=root.text("robot_base_frame", "base_link").lstrip("/"),
            transform_tolerance=root.number("transform_tolerance", 0.3),
            update_frequency=root.number("update_frequency", 5.0),
            publish_frequency=root.number("publish_frequency", 0.0),
            rolling_window=root.flag("rolling_window", False),
            track_unknown_space=track_unknown,
            always_send_full_costmap=root.flag("always_send_full_costmap", False),
            width=width,
            height=height,
            resolution=resolution,
            origin_x=root.number("origin_x", 0.0),
            origin_y=root.number("origin_y", 0.0),
            footprint=pad_footprint(unpadded, padding),
            footprint_padding=padding,
            layers=layers,
            pre_hydro=pre_hydro,
        )
