"""What the rqt pages (rqt_plot, rqt_console, rqt_image_view) share: a viser page of their
own under the viewer's access rules, its URL, and a thread that refreshes the page at a
steady rate, apart from the graph's executor (so a slow browser never holds a callback)."""

from __future__ import annotations

import contextlib
import io
import threading
from collections.abc import Callable, Sequence
from typing import Any

from belvedere.viewer._access import page_url, serve_viser, viewer_access

__all__ = ["ToolPage"]

_WIDE = 'div[style*="width: 388px"] { width: min(1200px, 98vw) !important; }'


class ToolPage:
    """A page titled ``title`` on ``host:port``; :meth:`refresh` runs ``rate_hz`` times a
    second on a thread of its own until :meth:`close`."""

    def __init__(
        self,
        title: str,
        *,
        host: str = "127.0.0.1",
        port: int = 8080,
        allow_origins: Sequence[str] = (),
        token: str | None = None,
        rate_hz: float = 10.0,
    ) -> None:
        self.title = title
        self.access = viewer_access(host, allow_origins=allow_origins, token=token)
        self.server = serve_viser(self.access, host, port)
        self.gui = self.server.gui
        # The page is the panel: wide, always open, no 3D scene to look at behind it.
        self.gui.configure_theme(control_width="large", show_logo=False, show_share_button=False)
        self.gui.main_panel.dock_right()
        self.gui.set_panel_label(title)
        # viser sizes its panel for controls beside a 3D view; here the panel is the page, so
        # widen it (viser has no option for that: the panel's inline width, overridden).
        self.gui.add_html(f"<style>{_WIDE}</style>")
        self.server.scene.set_up_direction("+z")
        self.server.scene.world_axes.visible = False
        self._stop = threading.Event()
        self._period = 1.0 / rate_hz
        self._thread: threading.Thread | None = None

    def start(self, refresh: Callable[[], Any]) -> None:
        """Call ``refresh`` every period on the page's thread (after the page is built)."""

        def loop() -> None:
            while not self._stop.wait(self._period):
                refresh()

        self._thread = threading.Thread(target=loop, name=f"belvedere-{self.title}", daemon=True)
        self._thread.start()

    @property
    def url(self) -> str:
        """Where to open the page (with ``?token=…`` when it needs one)."""
        return page_url(self.server, self.access)

    def close(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2)
        with contextlib.redirect_stdout(io.StringIO()):  # viser's "Server stopped"
            self.server.stop()
