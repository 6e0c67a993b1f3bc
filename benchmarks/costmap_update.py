"""One costmap update (``updateMap``) of the course's two costmaps against their periods.

The course's mbot costmaps (mbot_navigation/config/mbot): the global one on the cloister map
(400 x 400 cells, static + obstacle + inflation layers, 1 Hz) and the local rolling window
(6 m x 6 m at 0.05 m, obstacle + inflation, 5 Hz), each fed a 360-beam laser scan of the
cloister's walls taken from poses along a walk. Prints the median and worst wall time of an
update and its share of the update period.

Run: ``python benchmarks/costmap_update.py [--updates N]``.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.maps import load_map
from belvedere.nav.costmap import CostmapParams, LayeredCostmap, Observation
from belvedere.yamlfile import load_yaml_file

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
CONFIG = EXAMPLES / "mbot_navigation/config/mbot"


def _params(name: str) -> dict[str, Any]:
    common = load_yaml_file(CONFIG / "costmap_common_params.yaml").data
    own = load_yaml_file(CONFIG / f"{name}_params.yaml").data[name]
    return {**common, **own}


def _scan(
    walls: npt.NDArray[np.bool_], resolution: float, origin: tuple[float, float], pose: Any
) -> Observation:
    """360 rays from ``pose`` to the first wall cell (or 6 m), as points at 0.2 m height."""
    x, y = pose
    angles = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    steps = np.arange(1, int(6.0 / (resolution / 2)))[None, :] * (resolution / 2)
    px = x + np.cos(angles)[:, None] * steps
    py = y + np.sin(angles)[:, None] * steps
    i = np.clip(((px - origin[0]) / resolution).astype(int), 0, walls.shape[1] - 1)
    j = np.clip(((py - origin[1]) / resolution).astype(int), 0, walls.shape[0] - 1)
    hit = walls[j, i]
    first = np.where(hit.any(axis=1), hit.argmax(axis=1), steps.shape[1] - 1)
    rows = np.arange(len(angles))
    points = np.column_stack([px[rows, first], py[rows, first], np.full(len(angles), 0.2)])
    return Observation(np.array([x, y, 0.2]), points, 0)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--updates", type=int, default=40)
    args = parser.parse_args()
    grid_map = load_map(EXAMPLES / "mbot_navigation/maps/cloister_gmapping.yaml")
    walls = grid_map.data == 100
    origin = (grid_map.origin[0], grid_map.origin[1])
    walk = [(-5.5 + 11.0 * k / args.updates, -4.5) for k in range(args.updates)]
    for name, frequency in (("global_costmap", 1.0), ("local_costmap", 5.0)):
        costmap = LayeredCostmap(CostmapParams.from_mapping(_params(name)))
        if costmap.static_layers:
            costmap.set_map(grid_map.data, grid_map.resolution, origin, "map")
        times = []
        for k, (x, y) in enumerate(walk):
            now = k * round(1e9 / frequency)
            costmap.add_observation("scan", _scan(walls, grid_map.resolution, origin, (x, y)), now)
            started = time.perf_counter()
            costmap.update((x, y, 0.0), now)
            times.append(time.perf_counter() - started)
        m = costmap.master
        median, worst = statistics.median(times), max(times)
        print(
            f"{name}: {m.width} x {m.height} cells, update median {median * 1000:.1f} ms, "
            f"max {worst * 1000:.1f} ms = {median * frequency:.3f} of the "
            f"{1 / frequency:.1f} s update period"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
