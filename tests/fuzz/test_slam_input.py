"""Fuzzing what reads laser scans and odometry — the SLAM cores ``belvedere slam`` runs over a
bag (gmapping's and hector's), amcl and a costmap — with hostile readings: NaN, inf and huge
values in ranges, angles, increments, range limits, odometry and the laser's mount; beam counts
past the cap; jumps. Every run ends with maps within GRID_CELLS, finite poses, or belvedere's
own error — never another exception, a hang or unbounded memory."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np
import numpy.typing as npt
from hypothesis import given
from hypothesis import strategies as st

from belvedere.bounded import GRID_CELLS
from belvedere.errors import BelvedereError
from belvedere.graph import NS, Graph
from belvedere.maps import OccupancyMap, grid_message
from belvedere.nodes._costmap import Costmap2DROS
from belvedere.nodes.gmapping import GMappingCore, LaserMountError
from belvedere.nodes.hector_mapping import HectorCore
from belvedere.tf import TFBuffer, TFError
from tests.fuzz._mutate import fuzz_settings, run_bounded
from tests.nav import hostile

HOSTILE = (math.nan, math.inf, -math.inf, 1e30, -1e30, 1e308, 1e12, 1e7, 0.0, -1.0, 1e-300)
"""Values a hostile field takes (besides its own sane ones)."""

COUNTS = (0, 1, 3, 360, 360, 360, 1081, 4096, 65_537, 1_000_000)
"""Beam counts: none, a few, real lasers', and past the cap (refused before any work)."""


def _field(sane: float) -> st.SearchStrategy[float]:
    return st.one_of(st.just(sane), st.just(sane), st.sampled_from(HOSTILE))


@dataclass(frozen=True)
class Reading:
    """One scan and the odometry at its stamp, as drawn."""

    count: int
    angle_min: float
    increment: float | None
    range_min: float
    range_max: float
    spoiled: tuple[tuple[int, float], ...]
    """(beam, value) pairs put into the room's ranges; beam -1: every beam."""
    odometry: tuple[float, float, float] | None
    """None: the path's pose; else this one (a jump, NaN…)."""

    def ranges(self, pose: hostile.Pose) -> npt.NDArray[np.float64]:
        room = hostile.room_ranges(pose, max(self.count, 1))[: self.count]
        values = room.astype(np.float64)  # (float32 on the wire: 1e308 becomes inf there)
        for beam, value in self.spoiled:
            if beam < 0:
                values[:] = value
            elif self.count:
                values[beam % self.count] = value
        return values


readings = st.builds(
    Reading,
    st.sampled_from(COUNTS),
    _field(-math.pi),
    st.one_of(st.none(), st.none(), st.sampled_from(HOSTILE)),
    _field(0.1),
    _field(30.0),
    st.lists(st.tuples(st.integers(-1, 2000), st.sampled_from(HOSTILE)), max_size=4).map(tuple),
    st.one_of(
        st.none(),
        st.none(),
        st.tuples(_field(0.0), _field(0.0), _field(0.0)),
    ),
)
runs = st.tuples(
    st.lists(readings, min_size=1, max_size=6),
    st.one_of(st.just(hostile.LASER), st.tuples(_field(0.1), _field(0.0), _field(0.2))),
)


def _messages(
    run: list[Reading], mount: tuple[float, float, float]
) -> tuple[TFBuffer, list[tuple[Any, hostile.Pose]]]:
    """A TF buffer with the laser's mount and each reading's odometry, and the scans."""
    buffer = TFBuffer(cache_time=3600.0)
    buffer.set_message(hostile.mount(NS, mount), static=True)
    scans = []
    for i, (reading, pose) in enumerate(zip(run, hostile.path(len(run)), strict=True)):
        stamp = NS + i * NS // 10
        odom = reading.odometry or pose
        buffer.set_message(hostile.tf("odom", "base_link", odom, stamp))
        msg = hostile.scan(
            stamp,
            reading.ranges(pose),
            angle_min=reading.angle_min,
            increment=reading.increment,
            range_min=reading.range_min,
            range_max=reading.range_max,
        )
        scans.append((msg, pose))
    return buffer, scans


def _bounded(grid: OccupancyMap | None) -> None:
    if grid is not None:
        assert grid.data.size <= GRID_CELLS


@fuzz_settings(150)
@given(runs)
def test_gmapping_core_on_hostile_readings(run: tuple[list[Reading], Any]) -> None:
    readings_, mount = run
    with run_bounded(30):
        buffer, scans = _messages(readings_, mount)
        core = GMappingCore({"base_frame": "base_link", "linearUpdate": 0.05})
        for msg, _ in scans:
            try:
                if core.ready(msg, buffer):
                    core.process(msg, buffer)
            except (TFError, LaserMountError, BelvedereError):
                pass
        try:
            grid = core.occupancy()
        except BelvedereError:
            return
        _bounded(grid)
        if core.slam is not None:
            for sub in core.slam.submaps:
                assert sub.grid.field.size <= GRID_CELLS
            assert np.isfinite(core.slam.pose()).all()
        _, poses = core.trajectory()
        assert np.isfinite(poses).all()


@fuzz_settings(100)
@given(runs)
def test_hector_core_on_hostile_readings(run: tuple[list[Reading], Any]) -> None:
    readings_, mount = run
    with run_bounded(30):
        buffer, scans = _messages(readings_, mount)
        core = HectorCore({"base_frame": "base_link", "map_size": 256, "map_resolution": 0.05})
        for msg, _ in scans:
            try:
                if core.ready(msg, buffer):
                    core.process(msg, buffer)
            except (TFError, BelvedereError):
                pass
        _bounded(core.occupancy())
        _, poses = core.trajectory()
        assert np.isfinite(poses).all()


@cache
def _live() -> tuple[Graph, Any, Costmap2DROS]:
    """amcl and a rolling costmap on one graph (its time stands still: their methods are
    called directly, each example with a fresh TF buffer and a fresh filter)."""
    from belvedere.nodes.amcl import _AmclNode

    graph = Graph()
    node = graph.create_node("amcl")
    for key, value in {"use_map_topic": True, "base_frame_id": "base_link"}.items():
        node.set_param(f"~{key}", value)
    amcl = _AmclNode(node)
    costmap_node = graph.create_node("move_base")
    params = {
        "global_frame": "odom",
        "robot_base_frame": "base_link",
        "rolling_window": True,
        "width": 4.0,
        "height": 4.0,
        "transform_tolerance": 1e9,
        "robot_radius": 0.2,
        "observation_sources": "scan",
        "scan": {"data_type": "LaserScan", "topic": "/scan", "marking": True, "clearing": True},
    }
    for key, value in params.items():
        costmap_node.set_param(f"~local_costmap/{key}", value)
    costmap = Costmap2DROS(costmap_node, "local_costmap", TFBuffer())
    return graph, amcl, costmap


def _room_map() -> Any:
    data = np.zeros((220, 220), dtype=np.int8)
    data[10, 10:-10] = data[-11, 10:-10] = data[10:-10, 10] = data[10:-10, -11] = 100
    return grid_message(OccupancyMap(data, 0.05, (-5.5, -5.5, 0.0)), frame_id="map")


@fuzz_settings(100)
@given(runs)
def test_amcl_and_a_costmap_on_hostile_readings(run: tuple[list[Reading], Any]) -> None:
    readings_, mount = run
    _, amcl, costmap = _live()
    with run_bounded(30):
        buffer, scans = _messages(readings_, mount)
        amcl.buffer = buffer
        amcl.lasers.clear()
        amcl._handle_map(_room_map())
        costmap.buffer = buffer
        costmap.costmap.reset()
        for msg, _ in scans:
            amcl._process(msg)
            costmap.pending.clear()
            costmap._on_reading(msg, costmap.costmap.obstacle_layers[0].buffers["scan"].params)
            costmap.update_now()
        assert amcl.localizer is not None
        poses = amcl.localizer.filter.poses
        assert np.isfinite(poses).all()
        assert costmap.grid().costs.shape == (80, 80)
