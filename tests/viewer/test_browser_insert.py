"""Building a world in a real browser: models inserted from the Insert panel by a click on
the ground, one moved; a room drawn with the building editor, saved and inserted."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import GazeboRos, PhysicsSimulation
from belvedere.viewer import Viewer
from belvedere.world import ModelPaths, empty_world, read_world
from tests.conftest import EXAMPLES, free_port
from tests.viewer.docs_screenshots import docs_screenshot
from tests.viewer.test_browser import (
    BROWSER_DEADLINE,
    RGB,
    _pixel,
    browser_page,
    project,
    view_centre,
    wait_for_pixel,
)
from tests.waiting import wait_until
from tests.world.test_building import X0, assert_a_laser_in_the_middle_sees_the_room

pytestmark = pytest.mark.browser

PACKAGES = PackageIndex([EXAMPLES])


class World:
    """An empty physics world in a viewer, models looked up in the examples and in a
    home of the test's own."""

    def __init__(self, home: Path) -> None:
        self.graph = Graph()
        packages = PACKAGES
        # as `belvedere sim --engine physics` makes it
        world = empty_world(model_paths=ModelPaths.from_environment(packages=packages))
        self.sim = PhysicsSimulation(self.graph, world)
        GazeboRos(self.sim, packages=packages)
        self.viewer = Viewer(
            self.graph,
            port=free_port(),
            sim=self.sim,
            packages=packages,
            world=world,
            world_poses=self.sim.model_poses,
            fixed_frame="world",
        )
        panel = self.viewer.insert
        assert panel is not None
        assert panel.editor is not None
        self.panel, self.editor = panel, panel.editor
        assert panel.paths.directories[0] == home / ".gazebo" / "models"
        self.graph.start(rtf=1.0)

    def close(self) -> None:
        self.viewer.close()
        self.graph.shutdown()


@pytest.fixture
def world(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[World]:
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.delenv("GAZEBO_MODEL_PATH", raising=False)
    w = World(tmp_path)
    yield w
    w.close()


def _choose(page: Any, label: str, option: str) -> None:
    """Pick ``option`` in the panel's dropdown ``label``."""
    page.get_by_label(label, exact=True).click()
    page.get_by_role("option", name=option, exact=True).click()


def _position(sim: PhysicsSimulation, name: str) -> tuple[float, float, float]:
    x, y, z = sim.model_pose(name)[:3, 3]
    return (float(x), float(y), float(z))


def orange(rgb: RGB) -> bool:
    r, g, b = rgb
    return r > 150 and 0.25 * r < g < 0.8 * r and b < 60


def grey(rgb: RGB) -> bool:
    r, g, b = rgb
    return max(r, g, b) - min(r, g, b) < 25 and 60 < r < 215


BOX, POST, MOVED = (-1.5, 1.5), (-0.3, 0.6), (0.0, 1.5)
"""Floor points in the initial view, right of the docked panel."""


def test_insert_two_models_and_move_one(world: World, tmp_path: Path) -> None:
    sim = world.sim
    with browser_page(world.viewer.url) as page:
        # a unit box (dynamic) where the ground is clicked
        page.get_by_role("button", name="Place (then click the ground)").click()
        wait_until(lambda: world.panel.armed == "Box", what="Box armed")
        page.mouse.click(*project((*BOX, 0.0)))
        wait_until(lambda: "unit_box" in sim.world_roots, what="unit_box in the simulation")
        assert world.sim.world.model("unit_box") is not None
        assert math.dist(_position(sim, "unit_box")[:2], BOX) < 0.03  # a pixel: ~1 cm
        wait_until(lambda: abs(_position(sim, "unit_box")[2] - 0.5) < 0.01, what="box on the floor")
        wait_for_pixel(page, project((*BOX, 0.5)), grey, what="the unit box's top")
        # the library's orange post (static, from model://belvedere_post)
        _choose(page, "Model", "belvedere_post")
        page.get_by_role("button", name="Place (then click the ground)").click()
        wait_until(lambda: world.panel.armed == "belvedere_post", what="post armed")
        page.mouse.click(*project((*POST, 0.0)))
        wait_until(lambda: "belvedere_post" in sim.world_roots, what="the post in the simulation")
        post = sim.world.model("belvedere_post")
        assert post is not None
        assert (post.uri, post.static) == ("model://belvedere_post", True)
        wait_for_pixel(page, project((*POST, 0.5)), orange, what="the post")
        # move the box: select it, type its new place, apply
        _choose(page, "Selected", "unit_box")
        fields = world.panel.fields
        # the fields show the selected box's pose first: typing before that lands is overwritten
        wait_until(
            lambda: fields["Y (m)"].value == pytest.approx(BOX[1], abs=0.03),
            what="the fields showing the box's pose",
            detail=lambda: {k: h.value for k, h in fields.items()},
        )
        for label, value in (("X (m)", MOVED[0]), ("Y (m)", MOVED[1])):
            field = page.get_by_label(label, exact=True)
            # typing "-1.5" over a negative number flips its sign in viser's number box:
            # empty it first, as a user would
            field.fill("")
            field.fill(str(value))
            field.press("Enter")
            wait_until(
                lambda: fields[label].value == value,  # noqa: B023
                what=f"{label} = {value} in the panel",
                detail=lambda: fields[label].value,  # noqa: B023
            )
        page.get_by_role("button", name="Apply pose").click()
        wait_until(
            lambda: math.dist(_position(sim, "unit_box")[:2], MOVED) < 0.02,
            what=f"the box moved to {MOVED}",
            detail=lambda: _position(sim, "unit_box"),
        )
        assert world.panel.gizmo.visible
        _choose(page, "Selected", "(none)")  # the gizmo covers the box's middle
        wait_until(lambda: not world.panel.gizmo.visible, what="the gizmo hidden")
        wait_for_pixel(page, project((*MOVED, 0.5)), grey, what="the moved box")
        assert not grey(_pixel(page, project((*BOX, 0.5))))
        assert _position(sim, "belvedere_post")[:2] == pytest.approx(POST, abs=0.03)
    # saved and read back: the post from the model path by include, the box inline, both
    # where they are now
    saved = read_world(world.viewer.save_world(tmp_path / "two.world"), packages=PACKAGES)
    models = {m.name: m for m in saved.models}
    assert (models["belvedere_post"].uri, models["unit_box"].uri) == (
        "model://belvedere_post",
        None,
    )
    fresh = PhysicsSimulation(Graph(), saved)
    assert _position(fresh, "unit_box")[:2] == pytest.approx(MOVED, abs=0.02)
    assert _position(fresh, "belvedere_post")[:2] == pytest.approx(POST, abs=0.03)


SCALE = 50.0


def _top(xy: tuple[float, float]) -> tuple[float, float]:
    """The pixel of a floor point in the editor's top view (centred on the origin)."""
    cx, cy = view_centre()
    return (cx + xy[0] * SCALE, cy - xy[1] * SCALE)


def test_draw_a_room_with_a_door(world: World, tmp_path: Path) -> None:
    """Four walls and a door drawn in the top view, saved as a model and inserted; the world
    saved with File > Save World As, reloaded into a fresh simulation, and a laser robot in
    the room's middle sees the walls and the door where they were drawn."""
    sim = world.sim
    world.viewer.set_background((0, 0, 0))
    with browser_page(world.viewer.url) as page:
        client = wait_until(
            lambda: next(iter(world.viewer.server.get_clients().values()), None),
            what="the browser to connect",
            timeout=BROWSER_DEADLINE,
        )
        assert client is not None
        page.get_by_text("Building Editor").click()
        page.get_by_role("button", name="Start editing (top view)").click()
        wait_until(lambda: client.camera.position[2] > 50, what="the top view")
        corners = [(-2.0, -1.5), (2.0, -1.5), (2.0, 1.5), (-2.0, 1.5)]
        editor = world.editor
        aim = [(x + 0.06, y - 0.05) for x, y in corners]  # a little off: snapped to the grid

        def first_corner() -> bool:
            """The browser turns to the top view a moment after the server does: until it
            has, a click lands elsewhere (and is taken back)."""
            editor.end_wall()
            page.mouse.click(*_top(aim[0]))
            wait_until(lambda: editor.chain is not None, what="the click")
            return editor.chain == corners[0]

        wait_until(first_corner, what="the first corner where it was clicked", interval=0.5)
        for i, point in enumerate([*aim[1:], aim[0]], start=1):
            page.mouse.click(*_top(point))
            wait_until(
                lambda: len(editor.building.walls) == i,  # noqa: B023
                what=f"wall {i} drawn",
                detail=lambda: (editor.building.walls, editor.chain, editor.note.content),
            )
        wait_until(lambda: len(world.editor.building.walls) == 4, what="four walls")
        wait_until(
            lambda: world.editor.chain is None,
            what="the chain closed",
            detail=lambda: (editor.building.walls, editor.chain, editor.note.content),
        )
        _choose(page, "Draw", "Door")
        # the dropdown's update and the scene click are two messages: a click first is a wall's
        wait_until(lambda: editor.mode.value == "Door", what="the door tool chosen")
        page.mouse.click(*_top((1.0, -1.62)))
        wait_until(lambda: world.editor.building.openings, what="the door")
        door = world.editor.building.openings[0]
        assert door.wall == 0  # the wall from (-2, -1.5) towards +x
        door_x = (X0 + door.offset - door.width / 2, X0 + door.offset + door.width / 2)
        assert door_x[0] < 1.0 < door_x[1]  # where it was clicked
        page.get_by_role("button", name="Done (save and insert)").click()
        wait_until(lambda: "building" in sim.world_roots, what="the room in the simulation")
        directory = tmp_path / ".gazebo" / "models" / "building"
        assert (directory / "model.config").is_file()
        room = sim.world.model("building")
        assert room is not None
        assert (room.uri, room.static) == ("model://building", True)
        written = read_world(directory / "model.sdf").models[0]
        assert [link.pose for link in written.links] == [link.pose for link in room.links]
        assert not world.editor.building.walls  # the editor starts afresh
        pieces = [s.geometry for s in room.links[0].collisions]
        assert len(pieces) == 3  # beside, above and beside the door

        # from above: the walls' tops on the black background, the room's inside black
        def lit(rgb: RGB) -> bool:
            return min(rgb) > 120

        for x, y in [(0.0, -1.5), (2.0, 0.0), (0.0, 1.5), (-2.0, 0.0)]:
            wait_for_pixel(page, _top((x, y)), lit, what=f"the wall at ({x}, {y})")
        assert max(_pixel(page, _top((0.25, 0.25)))) < 60  # between grid lines
        docs_screenshot(page, "building_editor")

        # File > Save World As, and the saved world in a fresh simulation
        page.get_by_text("File", exact=True).click()
        # viser's text boxes are not tied to their labels (label for= names another id)
        box = page.locator("xpath=//label[normalize-space()='World file']/following::input[1]")
        box.fill(str(tmp_path / "room.world"))
        box.press("Enter")
        page.get_by_role("button", name="Save World As").click()
        saved = tmp_path / "room.world"
        wait_until(
            lambda: world.viewer.world_note.content == f"Saved `{saved}`.",
            what="the viewer to say it saved the world",
            detail=lambda: world.viewer.world_note.content,
        )
    reloaded = read_world(saved, packages=PACKAGES)
    uris = {m.name: m.uri for m in reloaded.models}
    assert uris == {"ground_plane": "model://ground_plane", "building": "model://building"}
    assert_a_laser_in_the_middle_sees_the_room(reloaded, thickness=0.15, door=door_x)
