"""The viewer's displays and the thread that draws them: the Displays tree (from an ``.rviz``
config, the panel or code; removed; saved back as a config), the Global Options that reset
them, and the render loop at the Frame Rate.
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from belvedere.description.urdf import RobotModel
from belvedere.graph import NS, Graph, GraphTopics, Node
from belvedere.msgs import short
from belvedere.sim import SAVE_WORLD, SAVE_WORLD_TYPE
from belvedere.tf import Transform, TransformListener
from belvedere.viewer._access import ViewerError
from belvedere.viewer._canvas import CanvasDrawing
from belvedere.viewer._catalog import DISPLAYS, UnsupportedDisplay, display_type
from belvedere.viewer._display import Display, DisplayContext, color_tuple
from belvedere.viewer._page import page_background
from belvedere.viewer._panel import DisplayPanel, global_status_markdown, set_handle
from belvedere.viewer._rviz import RvizConfig, RvizDisplay, RvizView, format_color, write_rviz
from belvedere.viewer._status import Level, Status
from belvedere.viewer._views import ViewState
from belvedere.viewer._windows import ImageWindows
from belvedere.viewer._world import WorldDrawing

if TYPE_CHECKING:
    import viser

__all__: list[str] = []

STATUS_PERIOD_S = 0.25
"""How often the panel's statuses and topic lists are refreshed (not every frame)."""


class _DisplayHost:
    """The displays part of :class:`~belvedere.viewer.Viewer` (which sets all of this up)."""

    graph: Graph
    node: Node
    scene: viser.SceneApi
    gui: viser.GuiApi
    ctx: DisplayContext
    tf: TransformListener
    topics: GraphTopics
    model: RobotModel | None
    rviz: RvizConfig | None
    fixed_frame: str
    world: WorldDrawing | None
    world_poses: Callable[[], Mapping[str, Transform]] | None
    canvases: list[CanvasDrawing]
    windows: ImageWindows
    displays: list[Display]
    panels: dict[int, DisplayPanel]
    global_status: Status
    rate_hz: float
    frames_rendered: int
    last_render_s: float
    render_cpu_s: float
    views: dict[int, tuple[Any, ViewState]]
    started_wall: float
    started_ros_ns: int
    _next_status: float
    _stop: threading.Event
    _lock: threading.Lock
    # made by the side panel
    frame_dropdown: viser.GuiDropdownHandle[str]
    background: viser.GuiRgbHandle
    status_text: viser.GuiMarkdownHandle
    displays_folder: viser.GuiFolderHandle
    add_note: viser.GuiMarkdownHandle
    time_texts: dict[str, viser.GuiTextHandle]

    def _frames(self) -> list[str]:
        return sorted(self.tf.buffer.frames() | {self.fixed_frame})

    # --- global options ------------------------------------------------------------------------
    def set_fixed_frame(self, frame: str) -> None:
        """rviz resets every display when the fixed frame changes."""
        if frame == self.fixed_frame:
            return
        with self._lock:
            self.fixed_frame = frame
            for display in self.displays:
                display.reset()
        if self.frame_dropdown.value != frame:
            if frame not in self.frame_dropdown.options:
                self.frame_dropdown.options = [*self.frame_dropdown.options, frame]
            set_handle(self.frame_dropdown, frame)

    def set_background(self, color: Any) -> None:
        rgb = color_tuple(color)
        self.scene.set_background_image(np.full((2, 2, 3), rgb, dtype=np.uint8), format="png")
        page_background(self.gui, rgb)
        if tuple(self.background.value) != rgb:
            set_handle(self.background, rgb)

    # --- displays ------------------------------------------------------------------------------
    def _add_initial_displays(self, rviz: RvizConfig | None) -> None:
        # rviz's dark grey without a config too: the scene's own white hides a white grid
        self.set_background(RvizConfig.background if rviz is None else rviz.background)
        if rviz is None:
            self.add_display("Grid", values={"Cell Size": 0.5, "Plane Cell Count": 40})
            if self.model is not None:
                self.add_display("RobotModel")
            self.add_display("TF", enabled=False)
            return
        for d in rviz.displays:
            self.add_config_display(d)

    def add_config_display(
        self, d: RvizDisplay, *, enabled: bool = True, groups: tuple[RvizDisplay, ...] = ()
    ) -> list[Display]:
        """The displays of an ``.rviz`` config entry (a group's, in order): class, name,
        Enabled flag and values; a class we do not draw is listed with an Error status
        naming it. Each remembers its groups, so a saved config has them again."""
        if d.cls == "rviz/Group":
            return [
                shown
                for child in d.children
                for shown in self.add_config_display(
                    child, enabled=enabled and d.enabled, groups=(*groups, d)
                )
            ]
        found = display_type(d.cls)
        values = _flat(d.properties)
        if found is None:
            display: Display = UnsupportedDisplay(
                self.ctx, d.name, rviz_class=d.cls, enabled=enabled and d.enabled
            )
            display.values.update(values)
        else:
            cls, implied = found
            if d.topic_key:
                values.pop(d.topic_key, None)
            display = cls(
                self.ctx,
                d.name or cls.type_name,
                topic=d.topic,
                values={**implied, **values},
                enabled=enabled and d.enabled,
            )
        display.source = d
        display.groups = groups
        self._register(display)
        return [display]

    def config(self, view: ViewState | None = None, camera: Any = None) -> RvizConfig:
        """The viewer as an ``.rviz`` config (File > Save Config): what was loaded, with the
        displays, global options and ``view`` as they are now."""
        base = self.rviz or RvizConfig.default()
        config = RvizConfig(
            fixed_frame=self.fixed_frame,
            background=color_tuple(self.background.value),
            frame_rate=round(self.rate_hz),
            default_light=base.default_light,
            displays=_grouped(self.displays),
            view=base.view,
            saved_views=base.saved_views,
            document=base.document,
        )
        if view is not None and camera is not None:
            config.view = RvizView(
                view.cls,
                "Current View",
                view.properties_from(camera, self.tf.buffer, self.fixed_frame),
            )
        return config

    def save_config(self, path: str | Path, client: Any = None) -> Path:
        """Write :meth:`config` (with ``client``'s view) to ``path`` atomically."""
        entry = self.views.get(client.client_id) if client is not None else None
        view, camera = (entry[1], entry[0].camera) if entry is not None else (None, None)
        write_rviz(self.config(view, camera), path)
        return Path(path)

    def save_world(self, path: str | Path, *, timeout: float = 60.0) -> Path:
        """Have the simulation write its world, as it is now, to ``path`` (its
        ``/gazebo/save_world`` service: written off its thread, atomically)."""
        text = os.fspath(path).strip()
        target = os.path.abspath(os.path.expanduser(text)) if text else ""
        response = self.node.call_service(
            SAVE_WORLD, SAVE_WORLD_TYPE, {"path": target}, timeout=timeout
        )
        if not response.success:
            raise ViewerError(response.status_message.removeprefix("SaveWorld: "))
        self.node.logger.info("saved the world to %s", response.path)
        return Path(response.path)

    def add_display(
        self,
        kind: str,
        topic: str | None = None,
        *,
        name: str | None = None,
        values: Mapping[str, Any] | None = None,
        enabled: bool = True,
    ) -> Display:
        """Add a display of ``kind`` (rviz's type name, e.g. ``LaserScan``, or its class)."""
        found = display_type(kind)
        if found is None:
            msg = f"no display type {kind!r} (types: {', '.join(sorted(DISPLAYS))})"
            raise ViewerError(msg)
        cls, implied = found
        display = cls(
            self.ctx,
            name or cls.type_name,
            topic=topic,
            values={**implied, **(values or {})},
            enabled=enabled,
        )
        self._register(display)
        return display

    def _register(self, display: Display) -> None:
        with self._lock:
            self.displays.append(display)
        with self.displays_folder:
            self.panels[id(display)] = DisplayPanel(
                self.gui,
                display,
                topics=self.topics.of_type,
                frames=self._frames,
                on_remove=self.remove_display,
            )

    def remove_display(self, display: Display) -> None:
        with self._lock:
            if display in self.displays:
                self.displays.remove(display)
        panel = self.panels.pop(id(display), None)
        if panel is not None:
            panel.remove()
        display.remove()

    def _add_from_gui(self, kind: str, topic: str) -> None:
        cls = DISPLAYS[kind]
        if cls.msg_type:
            found = self.topics.type_of(topic)
            if found is not None and short(found) != short(cls.msg_type):
                self.add_note.content = (
                    f"**Refused:** topic `{topic}` is of type `{short(found)}`; "
                    f"a {kind} display shows `{short(cls.msg_type)}`."
                )
                return
        self.add_display(kind, topic if cls.msg_type else None)
        self.add_note.content = f"Added {kind}" + (f" on `{topic}`." if cls.msg_type else ".")

    # --- rendering -------------------------------------------------------------------------------
    def _render_loop(self) -> None:
        next_at = time.monotonic()
        while not self._stop.is_set():
            start, cpu = time.monotonic(), time.thread_time()
            try:
                self.render_once()
            except Exception:
                self.node.logger.exception("viewer frame failed")
            self.last_render_s = time.monotonic() - start
            self.render_cpu_s += time.thread_time() - cpu
            period = 1.0 / max(1.0, self.rate_hz)
            next_at = max(next_at + period, time.monotonic())  # drop frames when late
            self._stop.wait(max(0.0, next_at - time.monotonic()))

    def render_once(self) -> None:
        fixed = self.fixed_frame
        buffer = self.tf.buffer
        with self._lock:
            displays = list(self.displays)
        for display in displays:
            try:
                display.render(fixed)
            except Exception as err:  # a display's bug must not stop the others
                if display.status.get("Display") is None:
                    self.node.logger.exception("display %s failed", display.name)
                display.status.set("Display", Level.ERROR, f"drawing failed: {err!r}")
        if self.world is not None and self.world_poses is not None:
            self.world.update(self.world_poses())
        for canvas in self.canvases:
            canvas.update()
        self.windows.render()
        for client, view in list(self.views.values()):
            view.follow(client.camera, buffer, fixed)
        now = time.monotonic()
        if now >= self._next_status:
            self._next_status = now + STATUS_PERIOD_S
            self._refresh_panel(fixed, displays)
        self.frames_rendered += 1

    def _refresh_panel(self, fixed: str, displays: list[Display]) -> None:
        buffer = self.tf.buffer
        frames = self._frames()
        if list(self.frame_dropdown.options) != frames:
            self.frame_dropdown.options = frames
        if buffer.frame_exists(fixed) or not buffer.frames():
            self.global_status.set(
                "Fixed Frame",
                Level.OK if buffer.frame_exists(fixed) else Level.WARN,
                "OK" if buffer.frame_exists(fixed) else "No tf data.  Actual error: no frames",
            )
        else:
            self.global_status.set(
                "Fixed Frame",
                Level.ERROR,
                f"No tf data.  Actual error: Fixed Frame [{fixed}] does not exist",
            )
        self.windows.refresh()
        text = global_status_markdown(self.global_status, displays)
        if self.status_text.content != text:
            self.status_text.content = text
        for display in displays:
            panel = self.panels.get(id(display))
            if panel is not None:
                panel.refresh()
        ros_ns = self.graph.now_ns()
        wall = time.time()
        for label, value in (
            ("ROS Time", f"{ros_ns / NS:.2f}"),
            ("ROS Elapsed", f"{(ros_ns - self.started_ros_ns) / NS:.2f}"),
            ("Wall Time", f"{wall:.2f}"),
            ("Wall Elapsed", f"{wall - self.started_wall:.2f}"),
        ):
            set_handle(self.time_texts[label], value)


def _flat(properties: Mapping[str, Any]) -> dict[str, Any]:
    """rviz's nested properties (``Line Style: {Value: Lines, Line Width: 0.03}``) as the
    flat names the panel shows (``Line Style``, ``Line Width``)."""
    flat: dict[str, Any] = {}
    for key, value in properties.items():
        if isinstance(value, dict):
            if "Value" in value:
                flat[key] = value["Value"]
            for sub, inner in _flat({k: v for k, v in value.items() if k != "Value"}).items():
                flat.setdefault(sub, inner)
        else:
            flat[key] = value
    return flat


def _grouped(displays: list[Display]) -> list[RvizDisplay]:
    """The displays' config entries, inside the groups they were read in (a group is written
    where its first remaining display is; one emptied by removals is left out)."""
    top: list[RvizDisplay] = []
    made: dict[int, RvizDisplay] = {}
    for display in displays:
        siblings = top
        for group in display.groups:
            entry = made.get(id(group))
            if entry is None:
                entry = made[id(group)] = RvizDisplay(
                    cls=group.cls,
                    name=group.name,
                    enabled=group.enabled,
                    properties=dict(group.properties),
                    children=[],
                )
                siblings.append(entry)
            siblings = entry.children
        siblings.append(_config_display(display))
    return top


def _config_display(display: Display) -> RvizDisplay:
    """A display as its config entry: the one it was read from (keeping what we do not
    model, and where nested values sit), updated with the values it has now."""
    source: RvizDisplay | None = display.source
    cls = display.rviz_class
    # Inside a disabled group a display is off whatever its own flag: keep the file's flag.
    off_by_group = not all(g.enabled for g in display.groups)
    entry = RvizDisplay(
        cls=cls,
        name=display.name,
        enabled=source.enabled if off_by_group and source is not None else display.enabled,
        properties=dict(source.properties) if source is not None else {},
        children=[],
    )
    known = {p.name: p for p in display.all_props()}
    paths = _paths(entry.properties)
    for key, value in display.values.items():
        prop = known.get(key)
        if prop is None and source is not None:
            continue  # kept as the file had it
        written = format_color(value) if prop is not None and prop.kind == "color" else value
        if key == "Topic" and entry.topic_key:
            key = entry.topic_key
        entry.set(paths.get(key, key), written)
    return entry


def _paths(properties: Mapping[str, Any], prefix: str = "") -> dict[str, str]:
    """Where each property name sits in rviz's nesting (``Line Width`` →
    ``Line Style/Line Width``)."""
    found: dict[str, str] = {}
    for key, value in properties.items():
        found.setdefault(key, prefix + key)
        if isinstance(value, dict):
            for name, path in _paths(value, f"{prefix}{key}/").items():
                found.setdefault(name, path)
    return found
