"""rqt_reconfigure in the browser: every dynamic_reconfigure server on the graph as a tree of
namespaces, and for each server ticked in it, its parameters (:mod:`._reconfigure_panel`).

A page of its own, served by viser with the viewer's access rules. The servers are looked for
again every ``poll`` seconds (services in other processes are only known by asking), and an
edit is sent by a worker thread of the page: a service call waits for its server, which the
GUI's thread must not.
"""

from __future__ import annotations

import contextlib
import io
import queue
import threading
from collections.abc import Iterable, Sequence
from typing import Any

from belvedere.graph import GraphTopics, Node
from belvedere.ros1.dynamic_reconfigure.graph_client import GraphClient, find_servers
from belvedere.viewer._access import page_url, serve_viser, viewer_access
from belvedere.viewer._reconfigure_panel import ServerPanel

__all__ = ["ReconfigurePage"]

_Tree = dict[str, "_Tree"]


def _tree(names: Iterable[str]) -> _Tree:
    """The namespaces of ``names`` as nested dicts (``/a/b`` is ``{"a": {"b": {}}}``)."""
    root: _Tree = {}
    for name in names:
        branch = root
        for part in name.strip("/").split("/"):
            branch = branch.setdefault(part, {})
    return root


class ReconfigurePage:
    """rqt_reconfigure's window as a page on ``host:port`` (0: a free port), for ``node``'s
    graph; ``select``: the servers to open at once (rqt_reconfigure's NODE arguments)."""

    def __init__(
        self,
        node: Node,
        *,
        host: str = "127.0.0.1",
        port: int = 0,
        select: Sequence[str] = (),
        allow_origins: Sequence[str] = (),
        token: str | None = None,
        poll: float = 1.0,
    ) -> None:
        self.node = node
        self.access = viewer_access(host, allow_origins=allow_origins, token=token)
        self.server = serve_viser(self.access, host, port)
        self.gui = self.server.gui
        self.gui.configure_theme(control_width="large", show_share_button=False)
        self.gui.set_panel_label("rqt_reconfigure")
        self.gui.main_panel.dock_left()  # beside the (empty) 3D view, as the viewer's panel
        self.server.scene.set_up_direction("+z")
        self.topics = GraphTopics(node.graph)
        self.poll = poll
        self.servers: list[str] = []
        """The servers found when last looked for."""
        self.panels: dict[str, ServerPanel] = {}
        """The ticked servers' parameters."""
        self.selected = {("/" + n.lstrip("/")).rstrip("/") for n in select}
        self._ticks: dict[str, Any] = {}
        self._lock = threading.RLock()
        self._tree_folder = self.gui.add_folder("Servers")
        with self._tree_folder:
            self._empty = self.gui.add_markdown("*looking for dynamic_reconfigure servers…*")
        self._tree_handles: list[Any] = []
        self._edits: queue.Queue[tuple[ServerPanel, str, Any] | None] = queue.Queue()
        self._stop = threading.Event()
        self._threads = [
            threading.Thread(target=self._look, name="rqt_reconfigure-look", daemon=True),
            threading.Thread(target=self._send, name="rqt_reconfigure-send", daemon=True),
        ]
        for thread in self._threads:
            thread.start()

    @property
    def url(self) -> str:
        """Where to open the page (with ``?token=…`` when it needs one)."""
        return page_url(self.server, self.access)

    # --- the tree of servers ---------------------------------------------------------------------
    def _look(self) -> None:
        while not self._stop.is_set():
            self.refresh()
            self._stop.wait(self.poll)

    def refresh(self) -> list[str]:
        """Look for the graph's servers now; redraw the tree if they changed."""
        if self.node.closed:
            return self.servers
        found = find_servers(self.node, self.topics)
        with self._lock:
            if found != self.servers:
                self.servers = found
                self._draw_tree()
            for name in sorted(self.selected & set(found)):
                self._open(name)
            for name in sorted(set(self.panels) - set(found)):
                self._close_panel(name)
        return found

    def _draw_tree(self) -> None:
        for handle in reversed(self._tree_handles):
            handle.remove()
        self._tree_handles, self._ticks = [], {}
        self._empty.visible = not self.servers
        self._empty.content = "*no dynamic_reconfigure server on the graph yet*"
        with self._tree_folder:
            self._draw_branch(_tree(self.servers), "")

    def _draw_branch(self, branch: _Tree, prefix: str) -> None:
        for part, below in sorted(branch.items()):
            name = f"{prefix}/{part}"
            if not below:
                self._tick(name, part)
                continue
            folder = self.gui.add_folder(part)
            self._tree_handles.append(folder)
            with folder:
                if name in self.servers:
                    self._tick(name, part)
                self._draw_branch(below, name)

    def _tick(self, name: str, label: str) -> None:
        box = self.gui.add_checkbox(label, name in self.selected, hint=name)
        self._tree_handles.append(box)
        self._ticks[name] = box

        def toggled(event: Any) -> None:
            del event
            self.select(name, bool(box.value))

        box.on_update(toggled)

    def select(self, name: str, shown: bool = True) -> None:
        """Show (or hide) server ``name``'s parameters, as ticking it in the tree does."""
        with self._lock:
            if shown:
                self.selected.add(name)
                if name in self.servers:
                    self._open(name)
            else:
                self.selected.discard(name)
                self._close_panel(name)
            box = self._ticks.get(name)
            if box is not None:
                box.value = shown

    def _open(self, name: str) -> None:
        if name not in self.panels:
            client = GraphClient(self.node, name)
            self.panels[name] = ServerPanel(self.gui, client, self._queue_edit)

    def _close_panel(self, name: str) -> None:
        panel = self.panels.pop(name, None)
        if panel is not None:
            panel.remove()

    # --- edits -------------------------------------------------------------------------------
    def _queue_edit(self, panel: ServerPanel, name: str, value: Any) -> None:
        self._edits.put((panel, name, value))

    def _send(self) -> None:
        while True:
            item = self._edits.get()
            if item is None:
                return
            # A dragged slider sends a value per step: only the latest of each waits its turn.
            pending = {(id(item[0]), item[1]): item}
            ending = False
            with contextlib.suppress(queue.Empty):
                while not ending:
                    more = self._edits.get_nowait()
                    ending = more is None
                    if more is not None:
                        pending[(id(more[0]), more[1])] = more
            for panel, name, value in pending.values():
                panel.send(name, value)
            if ending:
                return

    def close(self) -> None:
        self._stop.set()
        self._edits.put(None)
        for thread in self._threads:
            thread.join(timeout=5)
        with self._lock:
            for name in list(self.panels):
                self._close_panel(name)
        self.topics.close()
        with contextlib.redirect_stdout(io.StringIO()):  # viser's "Server stopped"
            self.server.stop()
