"""The building editor's model: walls drawn as segments, doors and windows cut into them,
made into one static model as Gazebo's building editor makes it.

Each wall is a link (posed at the wall's middle, x along the wall) holding boxes: the whole
wall when nothing is cut into it, else the pieces around each opening — full height beside
it, a lintel above it, a sill below a window. Walls reach half their thickness past their
ends, so walls meeting at an end close the corner. The model's frame sits at the middle of
the walls' extent, on the ground, so the model turns about its centre.
"""

from __future__ import annotations

import contextlib
import math
import re
from dataclasses import dataclass, replace
from pathlib import Path
from xml.sax.saxutils import escape

from belvedere.description.urdf import Box, Pose
from belvedere.errors import BelvedereError
from belvedere.fileio import StagedWrite, stage_write
from belvedere.world._model import RGBA, Material, Shape, WorldLink, WorldModelEntry

__all__ = [
    "DOOR",
    "WINDOW",
    "Building",
    "BuildingError",
    "Opening",
    "Piece",
    "Wall",
    "building_config",
    "building_sdf",
    "opening_at",
    "snap",
    "write_building",
]

Point = tuple[float, float]

THICKNESS = 0.15
HEIGHT = 2.5
"""Gazebo's building editor's default wall thickness and height (m)."""
GRID = 0.25
SNAP_RADIUS = 0.3
"""How near (m) a click must come to a wall's end to start or end there."""
WALL_RGBA: RGBA = (0.9, 0.9, 0.85, 1.0)

_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$")


class BuildingError(BelvedereError):
    """A building that cannot be made as asked (the drawing is unchanged)."""


@dataclass(frozen=True, slots=True)
class Wall:
    start: Point
    end: Point
    thickness: float = THICKNESS
    height: float = HEIGHT

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)

    @property
    def yaw(self) -> float:
        return math.atan2(self.end[1] - self.start[1], self.end[0] - self.start[0])

    @property
    def middle(self) -> Point:
        return ((self.start[0] + self.end[0]) / 2, (self.start[1] + self.end[1]) / 2)


@dataclass(frozen=True, slots=True)
class Opening:
    """A door or window: a hole through wall ``wall``."""

    wall: int
    """Index into :attr:`Building.walls`."""
    offset: float
    """The hole's middle, metres along the wall from its start."""
    width: float
    height: float
    sill: float = 0.0
    """The hole's bottom above the ground (0 for a door)."""
    kind: str = "door"


DOOR = Opening(0, 0.0, width=0.9, height=2.0, sill=0.0, kind="door")
WINDOW = Opening(0, 0.0, width=0.9, height=1.0, sill=1.0, kind="window")
"""Default sizes: copy with ``replace(DOOR, wall=…, offset=…)``."""


@dataclass(frozen=True, slots=True)
class Piece:
    """One box of a wall, in the wall's frame: x from ``x0`` to ``x1`` along the wall (0 at
    its start), z from ``z0`` to ``z1``."""

    x0: float
    x1: float
    z0: float
    z1: float


@dataclass(frozen=True, slots=True)
class Building:
    """What the user drew."""

    name: str = "building"
    walls: tuple[Wall, ...] = ()
    openings: tuple[Opening, ...] = ()
    rgba: RGBA = WALL_RGBA

    def with_wall(self, wall: Wall) -> Building:
        if wall.length < 1e-6:
            msg = f"a wall needs two different ends (both at {wall.start})"
            raise BuildingError(msg)
        if wall.thickness <= 0 or wall.height <= 0:
            msg = (
                "a wall needs a positive thickness and height, got "
                f"{wall.thickness} and {wall.height}"
            )
            raise BuildingError(msg)
        return replace(self, walls=(*self.walls, wall))

    def with_opening(self, opening: Opening) -> Building:
        """Also ``opening``, checked against its wall and the openings already in it."""
        if not 0 <= opening.wall < len(self.walls):
            msg = f"no wall {opening.wall} (the building has {len(self.walls)})"
            raise BuildingError(msg)
        wall = self.walls[opening.wall]
        what = f"the {opening.kind} on wall {opening.wall}"
        if opening.width <= 0 or opening.height <= 0 or opening.sill < 0:
            msg = f"{what} needs a positive width and height and a sill at or above the ground"
            raise BuildingError(msg)
        lo, hi = opening.offset - opening.width / 2, opening.offset + opening.width / 2
        if lo < -1e-9 or hi > wall.length + 1e-9:
            msg = (
                f"{what} ({opening.width:g} m wide at {opening.offset:g} m) does not fit in the "
                f"wall, which is {wall.length:g} m long"
            )
            raise BuildingError(msg)
        if opening.sill + opening.height > wall.height + 1e-9:
            msg = (
                f"{what} reaches {opening.sill + opening.height:g} m, above the wall's "
                f"{wall.height:g} m"
            )
            raise BuildingError(msg)
        for other in self.openings:
            if other.wall != opening.wall:
                continue
            if lo < other.offset + other.width / 2 and other.offset - other.width / 2 < hi:
                msg = f"{what} overlaps the {other.kind} at {other.offset:g} m"
                raise BuildingError(msg)
        return replace(self, openings=(*self.openings, opening))

    def pieces(self, index: int) -> list[Piece]:
        """The boxes of wall ``index``: around its openings, half a thickness past its ends."""
        wall = self.walls[index]
        half = wall.thickness / 2
        holes = sorted(
            (o for o in self.openings if o.wall == index), key=lambda o: o.offset - o.width / 2
        )
        out: list[Piece] = []
        x = -half
        for hole in holes:
            lo, hi = hole.offset - hole.width / 2, hole.offset + hole.width / 2
            if lo > x + 1e-9:
                out.append(Piece(x, lo, 0.0, wall.height))
            if hole.sill > 1e-9:
                out.append(Piece(lo, hi, 0.0, hole.sill))
            top = hole.sill + hole.height
            if top < wall.height - 1e-9:
                out.append(Piece(lo, hi, top, wall.height))
            x = hi
        if wall.length + half > x + 1e-9:
            out.append(Piece(x, wall.length + half, 0.0, wall.height))
        return out

    @property
    def centre(self) -> Point:
        """The middle of the walls' extent: where the model's frame goes."""
        xs = [p[0] for w in self.walls for p in (w.start, w.end)]
        ys = [p[1] for w in self.walls for p in (w.start, w.end)]
        if not xs:
            return (0.0, 0.0)
        return ((min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2)

    def entry(self) -> WorldModelEntry:
        """The model, its frame at :attr:`centre` (for drawing and for the simulation)."""
        cx, cy = self.centre
        links: list[WorldLink] = []
        material = Material(ambient=self.rgba, diffuse=self.rgba)
        for i, wall in enumerate(self.walls):
            boxes = []
            for j, piece in enumerate(self.pieces(i)):
                size = (piece.x1 - piece.x0, wall.thickness, piece.z1 - piece.z0)
                at = Pose(
                    ((piece.x0 + piece.x1) / 2 - wall.length / 2, 0.0, (piece.z0 + piece.z1) / 2)
                )
                boxes.append((f"Wall_{i}_{j}", Box(size), at))
            mx, my = wall.middle
            links.append(
                WorldLink(
                    name=f"Wall_{i}",
                    pose=Pose((mx - cx, my - cy, 0.0), (0.0, 0.0, wall.yaw)),
                    collisions=tuple(Shape(f"{n}_Collision", g, p) for n, g, p in boxes),
                    visuals=tuple(
                        Shape(f"{n}_Visual", g, p, rgba=self.rgba, material=material)
                        for n, g, p in boxes
                    ),
                )
            )
        return WorldModelEntry(
            name=self.name, pose=Pose((cx, cy, 0.0)), static=True, links=tuple(links)
        )


def snap(
    point: Point, walls: tuple[Wall, ...], *, grid: float = GRID, radius: float = SNAP_RADIUS
) -> Point:
    """Where a click at ``point`` draws: the nearest wall end within ``radius``, else the
    nearest grid point (no grid when ``grid`` is 0)."""
    ends = [p for w in walls for p in (w.start, w.end)]
    near = min(ends, key=lambda p: math.dist(p, point), default=None)
    if near is not None and math.dist(near, point) <= radius:
        return near
    if grid <= 0:
        return point
    return (round(point[0] / grid) * grid + 0.0, round(point[1] / grid) * grid + 0.0)


def opening_at(
    point: Point, building: Building, like: Opening, *, reach: float = SNAP_RADIUS
) -> Opening:
    """``like`` (a door or window) cut into the wall nearest ``point``, centred where the
    click falls on it, moved along the wall as far as needed to fit.

    Raises:
        BuildingError: no wall within ``reach`` of the wall's face, or none long enough.
    """
    best: tuple[float, int, float] | None = None
    for i, wall in enumerate(building.walls):
        dx, dy = wall.end[0] - wall.start[0], wall.end[1] - wall.start[1]
        along = ((point[0] - wall.start[0]) * dx + (point[1] - wall.start[1]) * dy) / wall.length
        along_clamped = min(max(along, 0.0), wall.length)
        foot = (
            wall.start[0] + dx * along_clamped / wall.length,
            wall.start[1] + dy * along_clamped / wall.length,
        )
        gap = math.dist(foot, point) - wall.thickness / 2
        if best is None or gap < best[0]:
            best = (gap, i, along_clamped)
    if best is None or best[0] > reach:
        x, y = point
        msg = f"no wall within {reach:g} m of ({x:.2f}, {y:.2f}) to put a {like.kind} in"
        raise BuildingError(msg)
    _, index, along = best
    length = building.walls[index].length
    if like.width > length:
        msg = f"a {like.width:g} m {like.kind} does not fit in wall {index} ({length:g} m long)"
        raise BuildingError(msg)
    offset = min(max(along, like.width / 2), length - like.width / 2)
    return replace(like, wall=index, offset=offset)


def _n(value: float) -> str:
    text = f"{value:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _v(*values: float) -> str:
    return " ".join(_n(v) for v in values)


def building_sdf(building: Building) -> str:
    """The model's ``model.sdf`` (SDF 1.6)."""
    entry = building.entry()
    r, g, b, a = building.rgba
    colour = _v(r, g, b, a)
    out = [
        "<?xml version='1.0'?>",
        "<sdf version='1.6'>",
        f"  <model name='{escape(entry.name)}'>",
        f"    <pose>{_v(*entry.pose.xyz, *entry.pose.rpy)}</pose>",
    ]
    for link in entry.links:
        out.append(f"    <link name='{link.name}'>")
        out.append(f"      <pose>{_v(*link.pose.xyz, *link.pose.rpy)}</pose>")
        for kind, shapes in (("collision", link.collisions), ("visual", link.visuals)):
            for shape in shapes:
                assert isinstance(shape.geometry, Box)
                out.append(f"      <{kind} name='{shape.name}'>")
                out.append(f"        <pose>{_v(*shape.pose.xyz, *shape.pose.rpy)}</pose>")
                size = _v(*shape.geometry.size)
                out.append(f"        <geometry><box><size>{size}</size></box></geometry>")
                if kind == "visual":
                    out.append(
                        f"        <material><ambient>{colour}</ambient>"
                        f"<diffuse>{colour}</diffuse></material>"
                    )
                out.append(f"      </{kind}>")
        out.append("    </link>")
    out += ["    <static>1</static>", "  </model>", "</sdf>", ""]
    return "\n".join(out)


def building_config(building: Building) -> str:
    """The model's ``model.config``: its name and SDF file, as Gazebo writes one."""
    name = escape(building.name)
    return (
        "<?xml version='1.0'?>\n"
        "<model>\n"
        f"  <name>{name}</name>\n"
        "  <version>1.0</version>\n"
        "  <sdf version='1.6'>model.sdf</sdf>\n"
        "  <author><name>belvedere</name><email></email></author>\n"
        "  <description>A building made with the building editor.</description>\n"
        "</model>\n"
    )


def write_building(building: Building, folder: str | Path) -> Path:
    """Write the model directory ``folder/NAME`` (``model.config`` and ``model.sdf``, both
    or neither). Returns the directory.

    Raises:
        BuildingError: no walls, a name that is no directory name, or the directory exists.
        FileWriteError: the files could not be written (nothing was).
    """
    if not building.walls:
        msg = "the building has no walls: draw some first"
        raise BuildingError(msg)
    if not _NAME.match(building.name):
        msg = (
            f"model name {building.name!r} is not a directory name (letters, digits, '_', "
            "'.', '-'; not starting with '.' or '-')"
        )
        raise BuildingError(msg)
    directory = Path(folder).expanduser() / building.name
    if directory.exists():
        msg = f"{directory} already exists; choose another model name (nothing was written)"
        raise BuildingError(msg)
    created = not directory.parent.exists()
    staged: list[StagedWrite] = []
    try:
        staged.append(stage_write(directory / "model.sdf", building_sdf(building), make_dirs=True))
        staged.append(stage_write(directory / "model.config", building_config(building)))
    except BaseException:
        for file in staged:
            file.discard()
        with contextlib.suppress(OSError):
            directory.rmdir()
            if created:
                directory.parent.rmdir()
        raise
    for file in staged:
        file.commit()
    return directory
