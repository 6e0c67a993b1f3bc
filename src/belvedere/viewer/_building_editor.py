"""The viewer's building editor: draw walls from above, cut doors and windows, and save the
result as a model directory that is inserted at once (Gazebo's building editor).

Start editing turns the tab's view to TopDownOrtho. In Wall mode each click ends a wall and
starts the next one there (snapped to the grid, or to a wall's end nearby); clicking where
the chain started closes it. In Door and Window mode a click near a wall cuts the opening
there. Done writes ``NAME/model.config`` and ``NAME/model.sdf`` under the chosen folder and
inserts the model.
"""

from __future__ import annotations

import logging
import os
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from belvedere.description.urdf import Pose
from belvedere.errors import BelvedereError
from belvedere.viewer._views import ViewState, floor_point
from belvedere.viewer._world import WorldDrawing
from belvedere.world import (
    DOOR,
    WINDOW,
    Building,
    LibraryModel,
    ModelPaths,
    Wall,
    WorldModel,
    WorldModelEntry,
    load_model,
    opening_at,
    snap,
    write_building,
)

if TYPE_CHECKING:
    import viser

__all__ = ["BuildingEditor", "EditorPanel", "EditorViewer"]

logger = logging.getLogger(__name__)

Point = tuple[float, float]
ROOT = "/building_editor"
TOP_VIEW_SCALE = 50.0
"""Pixels per metre of the editor's top view."""


class EditorViewer(Protocol):
    """What the building editor uses of the viewer (a :class:`~belvedere.viewer.Viewer`,
    handed to it through the Insert panel): its scene and panel, its active tool, and each
    tab's view."""

    @property
    def scene(self) -> viser.SceneApi: ...
    @property
    def gui(self) -> viser.GuiApi: ...

    tool: str | None

    @property
    def views(self) -> dict[int, tuple[Any, ViewState]]: ...


class EditorPanel(Protocol):
    """What the building editor uses of the Insert panel it inserts through."""

    @property
    def viewer(self) -> EditorViewer: ...

    armed: str | None

    @property
    def paths(self) -> ModelPaths: ...
    def insert_entry(self, entry: WorldModelEntry, pose: Pose) -> str: ...
    def refresh_library(self) -> None: ...


class BuildingEditor:
    """The Building Editor folder of the viewer's panel, inserting through ``panel``."""

    def __init__(self, panel: EditorPanel) -> None:
        self.panel = panel
        self.viewer = panel.viewer
        self.building = Building("building")
        self.history: list[Building] = []
        self.chain: Point | None = None
        """Where the next wall starts (None: the next click starts a chain)."""
        self.chain_first: Point | None = None
        self.editing = False
        self.preview: WorldDrawing | None = None
        self.marker: Any = None
        self._build_gui()
        self.viewer.scene.on_click()(self._on_click)

    def _build_gui(self) -> None:
        gui = self.viewer.gui
        with gui.add_folder("Building Editor", expand_by_default=False):
            gui.add_button("Start editing (top view)").on_click(lambda e: self.start(e.client))
            self.mode = gui.add_dropdown("Draw", ["Wall", "Door", "Window"], initial_value="Wall")
            self.mode.on_update(lambda _: self.end_wall())
            self.thickness = gui.add_number("Wall thickness (m)", 0.15, min=0.01, step=0.01)
            self.height = gui.add_number("Wall height (m)", 2.5, min=0.1, step=0.1)
            self.grid = gui.add_number("Grid (m)", 0.25, min=0.0, step=0.05)
            gui.add_button("End wall").on_click(lambda _: self.end_wall())
            gui.add_button("Undo").on_click(lambda _: self.undo())
            self.name = gui.add_text("Model name", "building")
            self.folder = gui.add_text("Save in", "~/.gazebo/models")
            gui.add_button("Done (save and insert)").on_click(self._done_clicked)
            gui.add_button("Discard").on_click(lambda _: self.discard())
            self.note = gui.add_markdown("")

    def _say(self, text: str) -> None:
        self.note.content = text

    # --- editing -------------------------------------------------------------------------------
    def start(self, client: Any = None) -> None:
        """Clicks draw from now on; ``client``'s tab looks straight down."""
        self.editing = True
        self.viewer.tool = None
        self.panel.armed = None
        if client is not None:
            view = ViewState(
                "rviz/TopDownOrtho", {"Scale": TOP_VIEW_SCALE, "Target Frame": "<Fixed Frame>"}
            )
            self.viewer.views[client.client_id] = (client, view)
        self._say("Click to draw walls; **End wall** ends a chain.")

    def _on_click(self, event: Any) -> None:
        if not self.editing or self.panel.armed is not None:
            return
        point = floor_point(event.ray_origin, event.ray_direction)
        if point is not None:
            self.click(point)

    def click(self, point: Point) -> None:
        """A click at floor point ``point`` in the current mode."""
        try:
            if self.mode.value == "Wall":
                self._wall_click(point)
            else:
                like = DOOR if self.mode.value == "Door" else WINDOW
                opening = opening_at(point, self.building, like)
                self._change(self.building.with_opening(opening))
                self._say(f"{like.kind.capitalize()} in wall {opening.wall}.")
        except BelvedereError as err:
            self._say(f"**Not drawn:** {err.message}")
        self._redraw()

    def _wall_click(self, point: Point) -> None:
        p = snap(point, self.building.walls, grid=float(self.grid.value))
        if self.chain is None:
            self.chain = self.chain_first = p
            self._say(f"Wall from ({p[0]:.2f}, {p[1]:.2f}): click its end.")
            return
        wall = Wall(
            self.chain, p, thickness=float(self.thickness.value), height=float(self.height.value)
        )
        self._change(self.building.with_wall(wall))
        self.chain = p
        if p == self.chain_first:
            self.end_wall()
            self._say(f"Closed: {len(self.building.walls)} walls.")
        else:
            self._say(f"{len(self.building.walls)} walls; click the next end.")

    def _change(self, building: Building) -> None:
        self.history.append(self.building)
        self.building = building

    def end_wall(self) -> None:
        self.chain = self.chain_first = None
        self._redraw()

    def undo(self) -> None:
        if self.history:
            self.building = self.history.pop()
        self.chain = self.chain_first = None
        self._redraw()

    def discard(self) -> None:
        self._change(Building(self.building.name))
        self.history.clear()
        self.editing = False
        self.end_wall()
        self._say("Discarded.")

    def _redraw(self) -> None:
        scene = self.viewer.scene
        if self.preview is not None:
            for name in list(self.preview.frames):
                self.preview.remove(name)
        self.preview = None
        if self.building.walls:
            self.preview = WorldDrawing(
                scene, WorldModel(models=(self.building.entry(),)), root=ROOT
            )
        if self.marker is not None:
            self.marker.remove()
            self.marker = None
        if self.chain is not None:
            self.marker = scene.add_icosphere(
                f"{ROOT}_marker", radius=0.08, color=(255, 120, 0), position=(*self.chain, 0.0)
            )

    # --- saving --------------------------------------------------------------------------------
    def _done_clicked(self, _: Any) -> None:
        self.done()

    def done(self) -> str | None:
        """Write the model directory and insert the model; the name it was inserted under
        (None when it could not be written: the drawing is kept)."""
        building = replace(self.building, name=str(self.name.value).strip())
        folder = Path(os.path.expanduser(str(self.folder.value).strip() or "~/.gazebo/models"))
        try:
            directory = write_building(building, folder)
            entry = self._load(directory)
        except BelvedereError as err:
            self._say(f"**Not saved:** {err.describe()}")
            return None
        logger.info("building editor: wrote %s", directory)
        name = self.panel.insert_entry(entry, entry.pose)
        self.history.clear()
        self.building = Building(building.name)
        self.editing = False
        self.end_wall()
        self.panel.refresh_library()
        self._say(f"Saved `{directory}` and inserted **{name}**.")
        return name

    def _load(self, directory: Path) -> WorldModelEntry:
        """The written model as an include reads it: ``model://NAME`` when its folder is on
        the model path, else by its directory (``file://…``)."""
        on_path = any(
            os.path.realpath(d) == os.path.realpath(directory.parent)
            for d in self.panel.paths.directories
        )
        uri = f"model://{directory.name}"
        paths = self.panel.paths if on_path else ModelPaths((directory.parent,))
        entry = load_model(LibraryModel(directory.name, uri, directory), paths)
        return entry if on_path else replace(entry, uri=f"file://{directory}")
