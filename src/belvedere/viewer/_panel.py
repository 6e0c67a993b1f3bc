"""rviz's Displays tree in viser's side panel: one folder per display with its enabled box,
status, properties, name and a Remove button."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.viewer._display import Display, Prop
from belvedere.viewer._status import Level, Status

__all__ = ["DisplayPanel", "folder_label", "set_handle"]

ICONS = {Level.OK: "✓", Level.WARN: "⚠", Level.ERROR: "✗"}


def set_handle(handle: Any, value: Any) -> None:
    """Set a GUI handle's value (viser allows it; its type stubs say read-only)."""
    handle.value = value


def folder_label(name: str, type_name: str, level: Level, enabled: bool) -> str:
    mark = ICONS[level] if enabled else "☐"
    return f"{mark} {name} ({type_name})"


class DisplayPanel:
    """The GUI of one display; :meth:`refresh` (render thread) keeps status and topic lists
    current."""

    def __init__(
        self,
        gui: Any,
        display: Display,
        *,
        topics: Callable[[str], list[str]],
        frames: Callable[[], list[str]],
        on_remove: Callable[[Display], None],
        order: float | None = None,
    ) -> None:
        self.gui = gui
        self.display = display
        self.topics = topics
        self.frames = frames
        self.controls: dict[str, Any] = {}
        self.shown: tuple[int, Level, bool, str] | None = None
        self.folder = gui.add_folder(self._label(), expand_by_default=False, order=order)
        with self.folder:
            enabled = gui.add_checkbox("Enabled", display.enabled)
            enabled.on_update(lambda _: display.set_enabled(bool(enabled.value)))
            self.enabled_box = enabled
            self.status_text = gui.add_markdown(display.status.markdown())
            for prop in display.all_props():
                self.controls[prop.name] = self._control(prop)
            name = gui.add_text("Name", display.name)
            name.on_update(lambda _: self._rename(str(name.value)))
            gui.add_button("Remove").on_click(lambda _: on_remove(display))

    def _label(self) -> str:
        d = self.display
        return folder_label(d.name, d.type_name, d.level, d.enabled)

    def _rename(self, name: str) -> None:
        if name.strip():
            self.display.name = name.strip()
            self.folder.label = self._label()

    def _control(self, prop: Prop) -> Any:
        gui, d = self.gui, self.display
        value = d.values.get(prop.name, prop.default)
        if prop.kind == "bool":
            handle = gui.add_checkbox(prop.name, bool(value))
        elif prop.kind == "color":
            handle = gui.add_rgb(prop.name, tuple(value))
        elif prop.kind == "choice":
            options = list(prop.options) if value in prop.options else [*prop.options, str(value)]
            handle = gui.add_dropdown(prop.name, options, initial_value=str(value))
        elif prop.kind == "topic":
            handle = gui.add_dropdown(prop.name, self._topic_options(), initial_value=str(value))
        elif prop.kind == "frame":
            handle = gui.add_dropdown(prop.name, self._frame_options(), initial_value=str(value))
        elif prop.kind == "text":
            handle = gui.add_text(prop.name, str(value))
        elif prop.name == "Alpha":
            handle = gui.add_slider(prop.name, 0.0, 1.0, 0.01, float(value))
        else:
            step = 1 if prop.kind == "int" else prop.step
            handle = gui.add_number(
                prop.name, value, min=prop.low, max=max(prop.high, value), step=step
            )

        def changed(_: Any) -> None:
            try:
                d.set_value(prop.name, handle.value)
            except BelvedereError as err:
                d.status.set(prop.name, Level.ERROR, err.message)

        handle.on_update(changed)
        return handle

    def _topic_options(self) -> list[str]:
        current = self.display.topic
        found = self.topics(self.display.msg_type)
        return sorted({*found, current} - {""}) or [current]

    def _frame_options(self) -> list[str]:
        return ["<Fixed Frame>", *self.frames()]

    def refresh(self) -> None:
        """Show the display's status and offer the graph's topics and frames (render thread)."""
        d = self.display
        shown = (d.status.version, d.level, d.enabled, d.name)
        if shown != self.shown:
            self.shown = shown
            self.status_text.content = d.status.markdown()
            self.folder.label = self._label()
            if bool(self.enabled_box.value) != d.enabled:
                set_handle(self.enabled_box, d.enabled)
        for prop in d.all_props():
            handle = self.controls[prop.name]
            if prop.kind == "topic":
                options = self._topic_options()
            elif prop.kind == "frame":
                options = self._frame_options()
            else:
                # a value the display chose itself (a cloud's colour transformer)
                if prop.kind == "choice" and handle.value != d.values.get(prop.name):
                    set_handle(handle, d.values[prop.name])
                continue
            if list(handle.options) != options:
                handle.options = options

    def remove(self) -> None:
        self.folder.remove()


def global_status_markdown(status: Status, displays: list[Display]) -> str:
    """Global Status, and the displays that are not Ok (rviz shows them in its tree)."""
    lines = [status.markdown()]
    for d in displays:
        if d.enabled and d.level is not Level.OK:
            worst = next(e for e in d.status.entries() if e[1] is d.level)
            lines.append(f"- {d.level.label} · {d.name}: {worst[0]}: {worst[2]}")
    return "\n".join(lines)
