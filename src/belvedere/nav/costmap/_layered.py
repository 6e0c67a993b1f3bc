"""costmap_2d's ``LayeredCostmap``: the master grid its layers write into, in plugin order."""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
import numpy.typing as npt

from belvedere.nav.costmap._footprint import radii
from belvedere.nav.costmap._grid import FREE, NO_INFORMATION, CostGrid
from belvedere.nav.costmap._layers import (
    Bounds,
    InflationLayer,
    Observation,
    ObstacleLayer,
    Pose2D,
    StaticLayer,
    Window,
    union,
)
from belvedere.nav.costmap._layers import whole as whole_grid
from belvedere.nav.costmap._params import CostmapParams, InflationParams, ObstacleParams

__all__ = ["Layer", "LayeredCostmap"]

Layer = StaticLayer | ObstacleLayer | InflationLayer


def _make(params: CostmapParams) -> list[tuple[str, Layer]]:
    layers: list[tuple[str, Layer]] = []
    for spec in params.layers:
        layer: Layer
        if isinstance(spec, ObstacleParams):
            layer = ObstacleLayer(spec)
        elif isinstance(spec, InflationParams):
            layer = InflationLayer(spec)
        else:
            layer = StaticLayer(spec)
        layers.append((spec.name, layer))
    return layers


class LayeredCostmap:
    """The layers of one costmap and the grid they make.

    Not rolling, the grid takes the static map's size, resolution and origin when a map
    arrives (before that, ``width``/``height``/``resolution``/``origin_*``). Rolling, it keeps
    its size and is re-centred on the robot at each update, moving by whole cells.

    As costmap_2d's ``updateMap``, an update rewrites only the box the obstacle layers touched
    (their rays, marks and the footprint's cells), grown by the inflation radius; the whole
    grid after a new map, a reset or clearing, a new footprint, and in a rolling window that
    moved or holds a static map.
    """

    def __init__(self, params: CostmapParams) -> None:
        self.params = params
        self.default = NO_INFORMATION if params.track_unknown_space else FREE
        cols = int(params.width / params.resolution)
        rows = int(params.height / params.resolution)
        self.master = CostGrid(
            np.full((rows, cols), self.default, dtype=np.uint8),
            params.resolution,
            params.origin_x,
            params.origin_y,
        )
        self.layers = _make(params)
        self.footprint = params.footprint
        self.inscribed_radius, self.circumscribed_radius = radii(self.footprint)
        self.size_locked = False
        self.updated = False
        self._whole = True
        """Whether the next update rewrites the whole grid."""
        self.last_window: Window | None = None
        """The cells (rows, columns) the last update rewrote; None when nothing changed."""
        for _, layer in self.layers:
            if isinstance(layer, ObstacleLayer):
                layer.match(self.master)

    @property
    def static_layers(self) -> list[StaticLayer]:
        return [layer for _, layer in self.layers if isinstance(layer, StaticLayer)]

    @property
    def obstacle_layers(self) -> list[ObstacleLayer]:
        return [layer for _, layer in self.layers if isinstance(layer, ObstacleLayer)]

    def set_footprint(self, footprint: npt.NDArray[np.float64]) -> None:
        self.footprint = footprint
        self.inscribed_radius, self.circumscribed_radius = radii(footprint)
        self._whole = True

    def _resize(self, rows: int, cols: int, resolution: float, x: float, y: float) -> None:
        self.master = CostGrid(
            np.full((rows, cols), self.default, dtype=np.uint8), resolution, x, y
        )
        for layer in self.obstacle_layers:
            layer.grid = None
            layer.match(self.master)
        self._whole = True

    def set_map(
        self,
        data: npt.NDArray[np.int8],
        resolution: float,
        origin: tuple[float, float],
        frame: str,
        *,
        layer: str | None = None,
    ) -> None:
        """A map (H, W) for the static layers (only the one named ``layer`` if given)."""
        taken = False
        for name, each in self.layers:
            if isinstance(each, StaticLayer) and layer in (None, name):
                taken |= each.set_map(data, resolution, origin, frame)
        self._whole |= taken
        if not taken or self.params.rolling_window:
            return
        m = self.master
        rows, cols = data.shape
        if (m.height, m.width, m.resolution, m.origin_x, m.origin_y) != (
            rows,
            cols,
            resolution,
            origin[0],
            origin[1],
        ):
            self._resize(rows, cols, resolution, origin[0], origin[1])
        self.size_locked = True

    def add_observation(self, source: str, observation: Observation, now_ns: int) -> None:
        for layer in self.obstacle_layers:
            if source in layer.buffers:
                layer.add(source, observation, now_ns)

    def sources(self) -> dict[str, tuple[ObstacleLayer, ...]]:
        """Each observation source's name and the layers that read it."""
        found: dict[str, tuple[ObstacleLayer, ...]] = {}
        for layer in self.obstacle_layers:
            for name in layer.buffers:
                found[name] = (*found.get(name, ()), layer)
        return found

    def current(self, now_ns: int) -> bool:
        return all(layer.current(now_ns) for layer in self.obstacle_layers)

    def footprint_at(self, pose: Pose2D) -> npt.NDArray[np.float64]:
        x, y, yaw = pose
        c, s = math.cos(yaw), math.sin(yaw)
        fp = self.footprint
        return np.column_stack([x + c * fp[:, 0] - s * fp[:, 1], y + s * fp[:, 0] + c * fp[:, 1]])

    def _follow(self, pose: Pose2D) -> bool:
        """Re-centre a rolling window on the robot; whether it moved."""
        m = self.master
        new_x = pose[0] - m.width * m.resolution / 2
        new_y = pose[1] - m.height * m.resolution / 2
        # costmap_2d moves the window by whole cells, truncating toward zero
        di = int((new_x - m.origin_x) / m.resolution)
        dj = int((new_y - m.origin_y) / m.resolution)
        if di == 0 and dj == 0:
            return False
        m.origin_x += di * m.resolution
        m.origin_y += dj * m.resolution
        for layer in self.obstacle_layers:
            layer.match(m)
        return True

    def update(self, pose: Pose2D, now_ns: int, *, map_to_global: Pose2D | None = None) -> None:
        """One ``updateMap``: follow the robot (rolling), let the obstacle layers take their
        observations and clear the footprint, then rebuild the part of the grid that can have
        changed, layer by layer. ``map_to_global`` places the static map in a rolling window
        (the pose of the map's frame in the global frame)."""
        whole = self._whole
        rolling = self.params.rolling_window
        if rolling:
            whole |= self._follow(pose)
            whole |= any(layer.map is not None for layer in self.static_layers)
        footprint = self.footprint_at(pose)
        touched: Bounds = None
        for obstacles in self.obstacle_layers:
            touched = union(touched, obstacles.update_bounds(now_ns, footprint))
        self._whole = False
        self.updated = True
        window = self._window(None if whole else touched, whole=whole)
        self.last_window = window
        if window is None:
            return
        self.master.costs[window] = self.default
        for _, layer in self.layers:
            if isinstance(layer, StaticLayer):
                layer.update(self.master, map_to_global, rolling, window)
            elif isinstance(layer, ObstacleLayer):
                layer.update(self.master, window)
            else:
                layer.update(self.master, self.inscribed_radius, window)

    def _window(self, touched: Bounds, *, whole: bool) -> Window | None:
        """The cells to rewrite: all, or those the inflation of the touched box can reach."""
        m = self.master
        if whole:
            return whole_grid(m)
        if touched is None:
            return None
        pad = max(
            (
                layer.reach(m.resolution)
                for _, layer in self.layers
                if isinstance(layer, InflationLayer)
            ),
            default=0,
        )
        i0, j0, i1, j1 = touched
        cols = slice(max(i0 - pad, 0), min(i1 + pad, m.width))
        rows = slice(max(j0 - pad, 0), min(j1 + pad, m.height))
        if cols.start >= cols.stop or rows.start >= rows.stop:
            return None
        return rows, cols

    def rebuild_all(self) -> None:
        """Make the next update rewrite the whole grid (as after a new map)."""
        self._whole = True

    def reset(self) -> None:
        """``resetLayers``: the grid and the obstacle layers back to their defaults."""
        self.master.costs[:] = self.default
        for layer in self.obstacle_layers:
            layer.reset()
        self._whole = True

    def clear_area(
        self, x: float, y: float, size: float, layers: Iterable[str], *, invert: bool = False
    ) -> tuple[list[str], list[str]]:
        """``ClearCostmapRecovery`` on the layers named (by the part of a layer's name after
        its last ``/``): static and obstacle layers have their cells outside the size x size
        square at (x, y) (inside it, with ``invert``) set to NO_INFORMATION. Returns the names
        that match no layer and those of layers without cells of their own (inflation)."""
        wanted = set(layers)
        found: set[str] = set()
        not_clearable: list[str] = []
        for name, layer in self.layers:
            short = name.rsplit("/", 1)[-1]
            if short not in wanted:
                continue
            found.add(short)
            if isinstance(layer, InflationLayer):
                not_clearable.append(short)
            else:
                layer.clear_area(x, y, size, invert=invert)
                self._whole = True
        return sorted(wanted - found), not_clearable
