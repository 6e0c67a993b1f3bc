"""The viewer's Insert panel (Gazebo's Insert tab and its move, rotate and delete tools)
for a physics simulation.

Choose a model (the library's, or a simple shape), press Place, click the ground: the model
appears where the pointer meets the floor and simulates at once, static or dynamic as its
SDF says. Any world model can be selected: a transform gizmo (and the pose fields) move and
turn it; Delete removes it. What changes the simulation runs on the graph's thread (posted
to its executor, which runs posts while paused too); the panel's callbacks never touch the
engine themselves.
"""

from __future__ import annotations

import logging
import math
import sys
import threading
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, Protocol

from belvedere.description.urdf import Pose
from belvedere.errors import BelvedereError
from belvedere.graph import Graph
from belvedere.tf import (
    Transform,
    quat_xyzw_from_rpy,
    rpy_from_quat_xyzw,
    wxyz_from_xyzw,
    xyzw_from_wxyz,
)
from belvedere.viewer._building_editor import BuildingEditor, EditorViewer
from belvedere.viewer._display import DisplayContext
from belvedere.viewer._panel import set_handle
from belvedere.viewer._views import floor_point
from belvedere.viewer._world import WorldDrawing
from belvedere.world import (
    SHAPES,
    LibraryModel,
    ModelPaths,
    WorldModel,
    WorldModelEntry,
    load_model,
    model_library,
    simple_shape,
)

if TYPE_CHECKING:
    from belvedere.sim.physics import PhysicsSimulation

__all__ = ["InsertPanel", "InsertViewer", "world_editing"]

logger = logging.getLogger(__name__)

NONE = "(none)"


class InsertViewer(EditorViewer, Protocol):
    """What the Insert panel uses of the viewer (a :class:`~belvedere.viewer.Viewer`): the
    building editor's part, and its display context, world drawing and poses, and graph."""

    @property
    def ctx(self) -> DisplayContext: ...

    world: WorldDrawing | None
    world_poses: Callable[[], Mapping[str, Transform]] | None

    @property
    def graph(self) -> Graph: ...


def _pose_of(t: Transform) -> Pose:
    x, y, z = t.translation
    return Pose((x, y, z), rpy_from_quat_xyzw(t.quat_xyzw))


class InsertPanel:
    """Insert, select, move and delete models of ``sim`` from ``viewer``."""

    def __init__(
        self,
        viewer: InsertViewer,
        sim: PhysicsSimulation,
        *,
        model_paths: ModelPaths | None = None,
    ) -> None:
        self.viewer = viewer
        self.sim = sim
        self.paths = model_paths or ModelPaths.from_environment(packages=viewer.ctx.packages)
        if viewer.world is None:
            viewer.world = WorldDrawing(viewer.scene, WorldModel())
        self.drawing: WorldDrawing = viewer.world
        self._sim_poses: Callable[[], Mapping[str, Transform]] = (
            viewer.world_poses or sim.model_poses
        )
        viewer.world_poses = self._poses
        self._last_poses: dict[str, Transform] = {}
        self._lock = threading.Lock()
        self._reserved: set[str] = set()
        """Names given to inserts the simulation has not made yet."""
        self.library: list[LibraryModel] = []
        self.choices: dict[str, LibraryModel | str] = {}
        self.armed: str | None = None
        """The choice the next ground click places."""
        self.selected: str | None = None
        self.dragging = False
        self._gizmo_at: Transform | None = None
        self.editor: BuildingEditor | None = None
        self._build_gui()
        self.refresh_library()
        self._refresh_selection()  # the world's own models can be moved too
        viewer.scene.on_click()(self._on_click)

    # --- GUI -----------------------------------------------------------------------------------
    def _build_gui(self) -> None:
        gui = self.viewer.gui
        with gui.add_folder("Insert"):
            self.choice = gui.add_dropdown("Model", ["Box"], initial_value="Box")
            gui.add_button("Place (then click the ground)").on_click(
                lambda _: self.arm(str(self.choice.value))
            )
            gui.add_button("Refresh model list").on_click(lambda _: self.refresh_library())
            self.note = gui.add_markdown("")
            self.broken = gui.add_markdown("")
        with gui.add_folder("Edit models"):
            self.selection = gui.add_dropdown("Selected", [NONE], initial_value=NONE)
            self.selection.on_update(lambda _: self.select(self._selection_value()))
            self.fields = {
                key: gui.add_number(key, 0.0, step=0.01)
                for key in ("X (m)", "Y (m)", "Z (m)", "Yaw (deg)")
            }
            gui.add_button("Apply pose").on_click(lambda _: self._apply_fields())
            gui.add_button("Delete model").on_click(lambda _: self._delete_selected())
        self.gizmo = self.viewer.scene.add_transform_controls(
            "/insert_gizmo", scale=0.8, visible=False, depth_test=False
        )
        self.gizmo.on_update(self._gizmo_moved)

    def refresh_library(self) -> None:
        """List the model path's models again (a model just copied into a directory)."""
        self.library = model_library(self.paths)
        choices: dict[str, LibraryModel | str] = {k.capitalize(): k for k in SHAPES}
        for model in self.library:
            if model.ok and not model.light:
                label = model.name if model.name not in choices else f"{model.name} ({model.uri})"
                choices[label] = model
        self.choices = choices
        self.choice.options = list(choices)
        broken = "".join(f"- ⚠ `{m.uri}`: {m.error}\n" for m in self.library if not m.ok)
        self.broken.content = broken and f"**Models that cannot be inserted:**\n\n{broken}"

    def _say(self, text: str) -> None:
        self.note.content = text

    def _selection_value(self) -> str | None:
        value = str(self.selection.value)
        return None if value == NONE else value

    def _refresh_selection(self) -> None:
        names = [NONE, *self.sim.world_roots]
        self.selection.options = names
        if self.selected not in names:
            self.selected = None
        set_handle(self.selection, self.selected or NONE)

    # --- inserting -----------------------------------------------------------------------------
    def arm(self, choice: str) -> None:
        """The next ground click places ``choice`` (the viewer's own tool steps aside)."""
        if choice not in self.choices:
            self._say(f"**Not placed:** no model {choice!r} in the list.")
            return
        self.viewer.tool = None
        self.armed = choice
        self._say(f"Click the ground to place **{choice}**.")

    def _on_click(self, event: Any) -> None:
        choice = self.armed
        if choice is None:
            return
        point = floor_point(event.ray_origin, event.ray_direction)
        if point is None:
            return
        self.armed = None
        self.insert(choice, point)

    def entry_of(self, choice: str) -> WorldModelEntry:
        """The model ``choice`` names, read now (a model file edited since is read anew)."""
        item = self.choices[choice]
        if isinstance(item, str):
            return simple_shape(item)
        return load_model(item, self.paths)

    def insert(self, choice: str, point: tuple[float, float], yaw: float = 0.0) -> str | None:
        """Place ``choice`` with its origin over ``point`` (its own height kept); the name
        it gets (Gazebo's: ``unit_box``, ``unit_box_0`` …), or None if it cannot be read."""
        try:
            entry = self.entry_of(choice)
        except BelvedereError as err:
            self._say(f"**Not placed:** {err.describe()}")
            return None
        pose = Pose((point[0], point[1], entry.pose.xyz[2]), (0.0, 0.0, yaw))
        return self.insert_entry(entry, pose)

    def insert_entry(self, entry: WorldModelEntry, pose: Pose) -> str:
        """Add ``entry`` to the simulation at ``pose`` under a free name (returned at once;
        the model appears when the simulation's thread has added it)."""
        with self._lock:
            name = self._free_name(entry.name)
            self._reserved.add(name)

        def add() -> None:
            try:
                self.sim.add_model(entry, name=name, pose=pose)
            except BelvedereError as err:
                self._say(f"**Not placed:** {err.describe()}")
                return
            finally:
                with self._lock:
                    self._reserved.discard(name)
            placed = self.sim.world.model(name)
            if placed is not None:
                self.drawing.add(placed)
            self._refresh_selection()
            x, y, _ = pose.xyz
            self._say(f"Placed **{name}** at ({x:.2f}, {y:.2f}).")
            logger.info("inserted model %s (%s) at %s", name, entry.uri or "inline", pose.xyz)

        self.viewer.graph.executor.post(add)
        return name

    def _free_name(self, base: str) -> str:
        taken = {*self.sim.model_names(), *self._reserved}
        if base not in taken:
            return base
        i = 0
        while f"{base}_{i}" in taken:
            i += 1
        return f"{base}_{i}"

    # --- selecting, moving, deleting -----------------------------------------------------------
    def select(self, name: str | None) -> None:
        """Show the gizmo on model ``name`` (None: on nothing)."""
        self.selected = name
        self._gizmo_at = None
        if self.selection.value != (name or NONE):
            set_handle(self.selection, name or NONE)
        self.gizmo.visible = name is not None
        if name is not None:
            pose = self._pose_now(name)
            if pose is not None:
                self._place_gizmo(pose)
                self._show_fields(pose)

    def _pose_now(self, name: str) -> Transform | None:
        moving = self._last_poses.get(name)
        if moving is not None:
            return moving
        entry = self.sim.world.model(name)
        if entry is None:
            return None
        x, y, z = entry.pose.xyz
        return Transform((x, y, z), quat_xyzw_from_rpy(*entry.pose.rpy))

    def _place_gizmo(self, t: Transform) -> None:
        self._gizmo_at = t
        self.gizmo.position = t.translation
        self.gizmo.wxyz = wxyz_from_xyzw(t.quat_xyzw)

    def _show_fields(self, t: Transform) -> None:
        x, y, z = t.translation
        yaw = math.degrees(rpy_from_quat_xyzw(t.quat_xyzw)[2])
        for key, value in zip(self.fields, (x, y, z, yaw), strict=True):
            set_handle(self.fields[key], round(value, 4))

    def _apply_fields(self) -> None:
        name = self.selected
        if name is None:
            self._say("Select a model first.")
            return
        x, y, z, yaw = (float(h.value) for h in self.fields.values())
        current = self._pose_now(name)
        roll, pitch, _ = rpy_from_quat_xyzw(current.quat_xyzw) if current else (0.0, 0.0, 0.0)
        self.move(name, Pose((x, y, z), (roll, pitch, math.radians(yaw))))

    def _gizmo_moved(self, event: Any) -> None:
        name = self.selected
        if name is None:
            return
        self.dragging = event.phase != "end"
        target = event.target
        t = Transform(
            tuple(float(v) for v in target.position),  # type: ignore[arg-type]
            xyzw_from_wxyz(tuple(float(v) for v in target.wxyz)),  # type: ignore[arg-type]
        )
        self._gizmo_at = t
        entry = self.sim.world.model(name)
        static = entry is None or entry.static or self.sim.world_roots.get(name) == "world"
        if static and event.phase != "end":
            # a static model is rebuilt where it is dropped; until then only its drawing moves
            self.drawing.update({name: t})
            return
        self.move(name, _pose_of(t))
        if event.phase == "end":
            self._show_fields(t)

    def move(self, name: str, pose: Pose) -> None:
        """Put model ``name`` at ``pose``: a dynamic one is teleported (at rest), a static
        one is rebuilt there (the engine cannot move what is welded to the world)."""

        def apply() -> None:
            sim = self.sim
            entry = sim.world.model(name)
            if entry is None:
                self._say(f"**Not moved:** no model {name!r} (deleted?).")
                return
            try:
                if sim.world_roots.get(name) == "world":
                    sim.delete(name)
                    sim.add_model(entry, name=name, pose=pose)
                else:
                    sim.set_model_pose(name, pose)
            except (BelvedereError, KeyError) as err:
                text = err.describe() if isinstance(err, BelvedereError) else str(err)
                self._say(f"**Not moved:** {text}")
                return
            x, y, z = pose.xyz
            t = Transform((x, y, z), quat_xyzw_from_rpy(*pose.rpy))
            self.drawing.update({name: t})
            if self.selected == name and not self.dragging:
                self._place_gizmo(t)

        self.viewer.graph.executor.post(apply)

    def _delete_selected(self) -> None:
        if self.selected is None:
            self._say("Select a model first.")
            return
        self.delete(self.selected)

    def delete(self, name: str) -> None:
        """Remove model ``name`` from the simulation and the scene."""

        def apply() -> None:
            try:
                self.sim.delete(name)
            except KeyError as err:
                self._say(f"**Not deleted:** {err}")
                return
            self.drawing.remove(name)
            if self.selected == name:
                self.select(None)
            self._refresh_selection()
            self._say(f"Deleted **{name}**.")

        self.viewer.graph.executor.post(apply)

    # --- every frame (render thread) -----------------------------------------------------------
    def _poses(self) -> Mapping[str, Transform]:
        """The movable models' poses, for the viewer's drawing; keeps the gizmo on the
        selected model while nobody drags it."""
        try:
            poses = dict(self._sim_poses())
        except (KeyError, RuntimeError):  # a model added or deleted while we read
            poses = self._last_poses
        self._last_poses = poses
        name = self.selected
        if name is not None and not self.dragging:
            now = poses.get(name)
            if now is not None and now != self._gizmo_at:
                self._place_gizmo(now)
        return poses


def world_editing(viewer: InsertViewer, sim: object) -> InsertPanel | None:
    """The Insert panel and the building editor, when ``sim`` is a physics simulation."""
    if "belvedere.sim.physics" not in sys.modules:
        return None  # no physics simulation was ever made (and mujoco stays unloaded)
    from belvedere.sim.physics import PhysicsSimulation

    if not isinstance(sim, PhysicsSimulation):
        return None
    panel = InsertPanel(viewer, sim)
    panel.editor = BuildingEditor(panel)
    return panel
