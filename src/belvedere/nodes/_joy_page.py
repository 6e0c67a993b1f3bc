"""A browser page that reads a gamepad through the Gamepad API and sends its axes and
buttons to joy_node: served on 127.0.0.1 by default, each state accepted only with the
page's secret and from the page's own origin."""

from __future__ import annotations

import json
import secrets
import threading
from collections.abc import Callable
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any, Final

__all__ = ["JoyPage"]

_MAX_BODY: Final = 16_384
_PAGE: Final = """<!doctype html>
<html><head><meta charset="utf-8"><title>joy_node</title></head>
<body style="font-family: sans-serif">
<h1>joy_node</h1>
<p id="status">No gamepad yet: connect one and press a button.</p>
<script>
const period = __PERIOD__;
let last = "";
let lastSent = 0;
function poll() {
  const pads = Array.from(navigator.getGamepads ? navigator.getGamepads() : []).filter(p => p);
  if (pads.length) {
    const pad = pads[0];
    document.getElementById("status").textContent = "Gamepad: " + pad.id;
    const state = JSON.stringify({
      axes: Array.from(pad.axes),
      buttons: Array.from(pad.buttons).map(b => (b.pressed ? 1 : 0)),
    });
    const now = performance.now();
    if (state !== last || (__REPEAT__ && now - lastSent >= __REPEAT__)) {
      last = state;
      lastSent = now;
      fetch("state?secret=__SECRET__", {method: "POST", body: state,
        headers: {"Content-Type": "application/json"}});
    }
  }
}
setInterval(poll, period);
</script></body></html>
"""


class JoyPage:
    """The page on ``host:port``; ``on_state(axes, buttons)`` for each state it sends."""

    def __init__(
        self,
        on_state: Callable[[list[float], list[int]], None],
        *,
        host: str = "127.0.0.1",
        port: int = 8093,
        poll_hz: float = 50.0,
        repeat_hz: float = 0.0,
    ) -> None:
        self.secret = secrets.token_urlsafe(16)
        self.received = 0
        page = (
            _PAGE.replace("__PERIOD__", str(max(1, round(1000 / poll_hz))))
            .replace("__REPEAT__", str(round(1000 / repeat_hz)) if repeat_hz > 0 else "0")
            .replace("__SECRET__", self.secret)
        )
        owner = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, format: str, *args: Any) -> None:
                del format, args  # the node's output is the graph's, not a request log

            def do_GET(self) -> None:
                if self.path.split("?")[0] not in ("/", "/index.html"):
                    self.send_error(404)
                    return
                body = page.encode()
                self.send_response(200)
                self.send_header("Content-Type", "text/html; charset=utf-8")
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)

            def do_POST(self) -> None:
                origin = self.headers.get("Origin")
                own = f"http://{self.headers.get('Host', '')}"
                if self.path != f"/state?secret={owner.secret}" or origin not in (None, own):
                    self.send_error(403)
                    return
                length = int(self.headers.get("Content-Length") or 0)
                if not 0 < length <= _MAX_BODY:
                    self.send_error(413)
                    return
                state = _state(self.rfile.read(length))
                if state is None:
                    self.send_error(400)
                    return
                owner.received += 1
                on_state(*state)
                self.send_response(204)
                self.end_headers()

        self.server = ThreadingHTTPServer((host, port), Handler)
        self.server.daemon_threads = True
        self.url = f"http://{host}:{self.server.server_address[1]}/"
        self._thread = threading.Thread(
            target=self.server.serve_forever, name="belvedere-joy-page", daemon=True
        )
        self._thread.start()

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()


def _state(body: bytes) -> tuple[list[float], list[int]] | None:
    """(axes, buttons) of a state the page sent, or None when it is not one."""
    try:
        data = json.loads(body)
    except ValueError:
        return None
    if not isinstance(data, dict):
        return None
    axes, buttons = data.get("axes"), data.get("buttons")
    if not isinstance(axes, list) or not isinstance(buttons, list):
        return None
    if len(axes) > 64 or len(buttons) > 128:
        return None
    if not all(isinstance(a, int | float) and not isinstance(a, bool) for a in axes):
        return None
    if not all(b in (0, 1) for b in buttons):
        return None
    return [max(-1.0, min(1.0, float(a))) for a in axes], [int(b) for b in buttons]
