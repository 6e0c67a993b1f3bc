"""The building editor's model: walls split around doors and windows, clicks snapped to the
grid and to wall ends, the model directory it writes read back by belvedere's SDF reader,
and a laser robot inside the room seeing the walls where they were drawn."""

from __future__ import annotations

import math
import os
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from belvedere.description.urdf import Box
from belvedere.fileio import FileWriteError
from belvedere.graph import Graph
from belvedere.sim.physics import PhysicsSimulation
from belvedere.world import (
    DOOR,
    WINDOW,
    Building,
    BuildingError,
    ModelPaths,
    Piece,
    Wall,
    WorldModel,
    load_model,
    model_library,
    opening_at,
    read_world,
    read_world_string,
    snap,
    write_building,
)
from tests.sim.test_sensors import _model

X0, X1, Y0, Y1 = -2.0, 2.0, -1.5, 1.5
"""The room's wall centre lines."""
T = 0.1
DOOR_AT = 3.0
"""The door's middle along the first wall (from (-2, -1.5) towards +x): x = 1."""


def _room(name: str = "room") -> Building:
    corners = [(X0, Y0), (X1, Y0), (X1, Y1), (X0, Y1)]
    building = Building(name)
    for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
        building = building.with_wall(Wall(a, b, thickness=T, height=2.5))
    return building.with_opening(replace(DOOR, wall=0, offset=DOOR_AT))


def test_an_opening_splits_its_wall() -> None:
    building = Building().with_wall(Wall((0.0, 0.0), (4.0, 0.0), thickness=0.2, height=2.5))
    assert building.pieces(0) == [Piece(-0.1, 4.1, 0.0, 2.5)]
    door = building.with_opening(replace(DOOR, offset=1.0))
    assert door.pieces(0) == [
        Piece(-0.1, 0.55, 0.0, 2.5),
        Piece(0.55, 1.45, 2.0, 2.5),  # the lintel
        Piece(1.45, 4.1, 0.0, 2.5),
    ]
    both = door.with_opening(replace(WINDOW, offset=3.0))
    assert both.pieces(0) == [
        Piece(-0.1, 0.55, 0.0, 2.5),
        Piece(0.55, 1.45, 2.0, 2.5),
        Piece(1.45, 2.55, 0.0, 2.5),
        Piece(2.55, 3.45, 0.0, 1.0),  # under the window
        Piece(2.55, 3.45, 2.0, 2.5),
        Piece(3.45, 4.1, 0.0, 2.5),
    ]


@pytest.mark.parametrize(
    ("opening", "message"),
    [
        (replace(DOOR, offset=0.3), r"the door on wall 0 \(0\.9 m wide at 0\.3 m\) does not fit"),
        (replace(WINDOW, offset=2.0, height=2.0), r"reaches 3 m, above the wall's 2\.5 m"),
        (replace(WINDOW, offset=1.5), r"the window on wall 0 overlaps the door at 1 m"),
        (replace(DOOR, wall=3), r"no wall 3 \(the building has 1\)"),
        (replace(DOOR, offset=2.0, width=0.0), r"needs a positive width"),
    ],
)
def test_bad_openings_are_refused(opening: object, message: str) -> None:
    building = Building().with_wall(Wall((0.0, 0.0), (4.0, 0.0)))
    building = building.with_opening(replace(DOOR, offset=1.0))
    with pytest.raises(BuildingError, match=message):
        building.with_opening(opening)  # type: ignore[arg-type]
    with pytest.raises(BuildingError, match=r"two different ends"):
        building.with_wall(Wall((1.0, 1.0), (1.0, 1.0)))


def test_clicks_snap_to_wall_ends_then_to_the_grid() -> None:
    walls = (Wall((0.0, 0.0), (2.1, 0.0)),)
    assert snap((2.3, 0.2), walls, grid=0.25) == (2.1, 0.0)  # the wall's end, off the grid
    assert snap((1.13, 0.6), walls, grid=0.25) == (1.25, 0.5)
    assert snap((-0.12, -0.13), (), grid=0.5) == (0.0, 0.0)
    assert snap((0.33, 0.77), (), grid=0.0) == (0.33, 0.77)


def test_a_click_near_a_wall_puts_the_opening_in_it() -> None:
    building = _room()
    door = opening_at((0.1, 1.6), building, DOOR)  # just outside the top wall (index 2)
    assert (door.wall, door.kind) == (2, "door")
    assert door.offset == pytest.approx(1.9)  # the top wall runs from x = 2 to x = -2
    near_end = opening_at((1.95, -1.45), building, WINDOW)  # a corner: moved to fit
    assert near_end.offset == pytest.approx(3.55)
    with pytest.raises(BuildingError, match=r"no wall within 0\.3 m of \(0\.00, 0\.00\)"):
        opening_at((0.0, 0.0), building, DOOR)


def test_the_written_model_reads_back(tmp_path: Path) -> None:
    building = _room()
    directory = write_building(building, tmp_path / "models")
    assert sorted(os.listdir(directory)) == ["model.config", "model.sdf"]
    model = read_world(directory / "model.sdf").models[0]
    assert (model.name, model.static, model.pose.xyz) == ("room", True, (0.0, 0.0, 0.0))
    assert [link.name for link in model.links] == ["Wall_0", "Wall_1", "Wall_2", "Wall_3"]
    wall = model.links[0]
    assert wall.pose.xyz == (0.0, -1.5, 0.0)
    sizes = [s.geometry for s in wall.collisions]
    assert sizes == [Box((2.6, 0.1, 2.5)), Box((0.9, 0.1, 0.5)), Box((0.6, 0.1, 2.5))]
    assert [s.pose.xyz for s in wall.collisions] == [
        pytest.approx((-0.75, 0.0, 1.25)),  # the wall's middle is its link's origin
        pytest.approx((1.0, 0.0, 2.25)),
        pytest.approx((1.75, 0.0, 1.25)),
    ]
    assert model.links[1].pose.rpy[2] == pytest.approx(math.pi / 2)
    assert len(wall.visuals) == 3
    assert wall.visuals[0].rgba == building.rgba
    # listed by its model.config name, included as model://room
    paths = ModelPaths((tmp_path / "models",))
    [listed] = [m for m in model_library(paths) if m.directory is not None]
    assert (listed.name, listed.uri, listed.ok) == ("room", "model://room", True)
    assert load_model(listed, paths).links == model.links


def test_writing_refuses_what_would_lose_something(tmp_path: Path) -> None:
    (tmp_path / "room").mkdir()
    with pytest.raises(BuildingError, match=r"room already exists; choose another model name"):
        write_building(_room(), tmp_path)
    with pytest.raises(BuildingError, match=r"no walls"):
        write_building(Building("empty"), tmp_path)
    with pytest.raises(BuildingError, match=r"model name 'my room' is not a directory name"):
        write_building(_room("my room"), tmp_path)
    not_a_folder = tmp_path / "notes.txt"  # even root cannot make a directory in a file
    not_a_folder.write_text("kept")
    with pytest.raises(FileWriteError, match=r"notes\.txt/room/model\.sdf"):
        write_building(_room(), not_a_folder)
    assert not_a_folder.read_text() == "kept"
    assert sorted(os.listdir(tmp_path)) == ["notes.txt", "room"]


def test_a_laser_inside_sees_the_drawn_walls_and_the_door(tmp_path: Path) -> None:
    """The room written to a model directory, included in a fresh world, and a laser robot
    at its middle: every beam ends on a wall's inner face (to a few cm), except through the
    door, where it reaches its maximum range."""
    write_building(_room(), tmp_path)
    world = read_world_string(
        "<sdf version='1.6'><world name='default'>"
        "<include><uri>model://ground_plane</uri></include>"
        "<include><uri>model://room</uri></include></world></sdf>",
        model_paths=ModelPaths((tmp_path,)),
    )
    assert_a_laser_in_the_middle_sees_the_room(world, thickness=T, door=(0.55, 1.45))


def assert_a_laser_in_the_middle_sees_the_room(
    world: WorldModel, *, thickness: float, door: tuple[float, float]
) -> None:
    """A laser robot at the world's origin, in a room whose walls' centre lines are the
    rectangle X0..X1 by Y0..Y1 (``thickness`` thick) with a door from x = door[0] to door[1]
    in the wall y = Y0: every beam ends on a wall's inner face (to a few cm), except through
    the door, where it reaches its maximum range."""
    model = _model(
        "mbot_with_laser_gazebo.xacro", **{"<stddev>0.01</stddev>": "<stddev>0</stddev>"}
    )
    graph = Graph()
    sim = PhysicsSimulation(graph, world)
    sim.spawn(model, name="mbot")
    scans: list[object] = []
    graph.create_node("probe").subscribe("/scan", "sensor_msgs/LaserScan", scans.append)
    graph.run(duration=1.0)
    scan = scans[-1]
    ranges = np.asarray(scan.ranges)  # type: ignore[attr-defined]
    angles = scan.angle_min + scan.angle_increment * np.arange(len(ranges))  # type: ignore[attr-defined]
    # the inner faces: half a thickness inside the drawn lines
    fx, fy = X1 - thickness / 2, Y1 - thickness / 2
    c, s = np.abs(np.cos(angles)), np.abs(np.sin(angles))
    with np.errstate(divide="ignore"):
        expected = np.minimum(
            np.where(c > 1e-12, fx / c, np.inf), np.where(s > 1e-12, fy / s, np.inf)
        )
    # where each beam meets the wall line y = -fy
    hits_bottom = (np.sin(angles) < 0) & (expected == np.where(s > 1e-12, fy / s, np.inf))
    x_at = np.where(hits_bottom, fy * np.cos(angles) / np.maximum(s, 1e-12), np.nan)
    x_out = x_at * (fy + thickness) / fy  # where it leaves the wall's outer face
    through = hits_bottom & (x_at > door[0] + 0.02) & (x_out < door[1] - 0.02)
    jamb = hits_bottom & ~through & (x_at > door[0] - 0.1) & (x_out < door[1] + 0.1)
    on_walls = ~through & ~jamb
    assert through.sum() >= 10  # the door spans ~14 degrees seen from the middle
    assert np.max(np.abs(ranges[on_walls] - expected[on_walls])) < 0.03
    assert np.all(np.isposinf(ranges[through]))  # out through the door, beyond range_max
