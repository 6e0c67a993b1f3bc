"""One dynamic_reconfigure server's parameters as rqt_reconfigure shows them: a widget per
parameter of its ``parameter_descriptions`` (a slider with its number field for a bounded int
or double, a number field for an unbounded one, a checkbox for a bool, a dropdown for an enum, a
text field for a string), its groups as folders or tabs, the values following
``parameter_updates``, and each edit sent through ``set_parameters`` with the value the
server kept shown in its place."""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Mapping
from typing import Any, Final

from belvedere.graph import GraphError
from belvedere.ros1.dynamic_reconfigure._description import Description, Group, Param
from belvedere.ros1.dynamic_reconfigure.graph_client import GraphClient

__all__ = ["ServerPanel"]

SLIDER_STEPS: Final = 100
"""A double's slider moves in hundredths of its range, as rqt_reconfigure's does."""

Send = Callable[["ServerPanel", str, Any], None]
"""Hands an edit to the page's worker, which calls :meth:`ServerPanel.send` off the GUI's
thread (a service call waits for the server)."""


def _hint(param: Param) -> str:
    if param.type in ("int", "double"):
        return f"{param.description} ({param.type}, {param.min} to {param.max})"
    return f"{param.description} ({param.type})"


def _enum_labels(param: Param) -> dict[str, Any]:
    """The dropdown's labels (``Name (value)``, as rqt_reconfigure's combo box shows them)
    and the value each stands for."""
    return {f"{name} ({value!r})": value for value, name in param.enum.items()}


class _Widget:
    """The GUI handles of one parameter, and how a value goes into and out of them."""

    def __init__(self, gui: Any, param: Param, value: Any, edited: Callable[[Any], None]) -> None:
        self.param = param
        self.handles: list[Any] = []
        self._labels = _enum_labels(param)
        hint = _hint(param)
        if self._labels:
            label = self._label_of(value)
            self.handles.append(
                gui.add_dropdown(param.name, tuple(self._labels), initial_value=label, hint=hint)
            )
        elif param.type == "bool":
            self.handles.append(gui.add_checkbox(param.name, bool(value), hint=hint))
        elif param.type == "str":
            self.handles.append(gui.add_text(param.name, str(value), hint=hint))
        else:
            self._add_number(gui, param, value, hint)
        for handle in self.handles:
            handle.on_update(self._from(handle, edited))

    def _add_number(self, gui: Any, param: Param, value: Any, hint: str) -> None:
        whole = param.type == "int"
        if math.isfinite(param.min) and math.isfinite(param.max) and param.min < param.max:
            # viser's slider has its number field beside it, bounded to the slider's range
            step = 1 if whole else (param.max - param.min) / SLIDER_STEPS
            shown = min(max(value, param.min), param.max)
            self.handles.append(
                gui.add_slider(param.name, param.min, param.max, step, shown, hint=hint)
            )
            return
        # Unbounded: any number, and what the server clamps or corrects shows up in its place.
        number = int(value) if whole else float(value)
        step = 1 if whole else None
        self.handles.append(gui.add_number(param.name, number, step=step, hint=hint))

    def _label_of(self, value: Any) -> str:
        for label, option in self._labels.items():
            if option == value:
                return label
        return next(iter(self._labels))

    def _from(self, handle: Any, edited: Callable[[Any], None]) -> Callable[[Any], None]:
        def on_update(event: Any) -> None:
            # Only a user's edit is sent: a value the server published is set here with no
            # client, and sending it back would echo every update to the server.
            if event.client is None:
                return
            value = handle.value
            if self._labels:
                value = self._labels.get(value, value)
            elif self.param.type == "int":
                value = round(value)
            edited(value)

        return on_update

    def show(self, value: Any) -> None:
        """Show ``value`` (the server's) in every handle."""
        if self._labels:
            value = self._label_of(value)
        for handle in self.handles:
            low, high = getattr(handle, "min", None), getattr(handle, "max", None)
            shown = value
            if low is not None and high is not None and isinstance(value, int | float):
                shown = min(max(value, low), high)  # a slider shows the end of its track
            handle.value = shown

    def remove(self) -> None:
        for handle in self.handles:
            handle.remove()


class ServerPanel:
    """Server ``client.name``'s parameters, in a folder of ``gui`` that follows its topics."""

    def __init__(self, gui: Any, client: GraphClient, send: Send) -> None:
        self.gui = gui
        self.client = client
        self._send = send
        self._lock = threading.RLock()
        self._drawn: Description | None = None
        self.widgets: dict[str, _Widget] = {}
        self._containers: list[Any] = []
        self.folder = gui.add_folder(client.name)
        with self.folder:
            self.status = gui.add_markdown("*waiting for the server's parameter_descriptions*")
        client.on_change = self._changed
        self._changed(client)

    def _changed(self, client: GraphClient) -> None:
        with self._lock:
            described = client.description
            if described is None:
                return
            if described is not self._drawn:
                self._draw(described, client.config)
            for name, value in client.config.items():
                widget = self.widgets.get(name)
                if widget is not None:
                    widget.show(value)

    def _draw(self, described: Description, config: Mapping[str, Any]) -> None:
        for widget in self.widgets.values():
            widget.remove()
        for container in reversed(self._containers):
            container.remove()
        self.widgets, self._containers = {}, []
        self._drawn = described
        with self.folder:
            self._draw_group(described.root, config)
        self.status.content = f"{len(self.widgets)} parameters"

    def _draw_group(self, group: Group, config: Mapping[str, Any]) -> None:
        for param in group.params:
            value = config.get(param.name, param.default)
            self.widgets[param.name] = _Widget(self.gui, param, value, self._sender(param.name))
        tabs = [g for g in group.groups if g.type == "tab"]
        for child in group.groups:
            if child.type == "tab" or child.type == "hide":
                continue
            folder = self.gui.add_folder(child.name, expand_by_default=child.type != "collapse")
            self._containers.append(folder)
            with folder:
                self._draw_group(child, config)
        if tabs:
            tab_group = self.gui.add_tab_group()
            self._containers.append(tab_group)
            for child in tabs:
                with tab_group.add_tab(child.name):
                    self._draw_group(child, config)

    def _sender(self, name: str) -> Callable[[Any], None]:
        return lambda value: self._send(self, name, value)

    def send(self, name: str, value: Any) -> None:
        """Send one edit; show the value the server kept (or why it refused)."""
        try:
            kept = self.client.set({name: value})
        except (GraphError, TimeoutError) as err:
            self.status.content = f"**{name} = {value!r} refused:** {err}"
            self._changed(self.client)  # back to the server's value
            return
        answer = kept.get(name)
        note = "" if answer == value else f" (the server kept {answer!r})"
        self.status.content = f"set {name} = {value!r}{note}"
        with self._lock:
            widget = self.widgets.get(name)
            if widget is not None and answer is not None:
                widget.show(answer)

    def remove(self) -> None:
        self.client.close()
        self.folder.remove()
