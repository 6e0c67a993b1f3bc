"""A browser page that reads a gamepad through the Gamepad API and sends its axes and
buttons to joy_node: served on 127.0.0.1 by default, each state accepted only with the
page's secret and from the page's own origin. The page sends each change; repeats are
joy_node's (``~autorepeat_rate``)."""

from __future__ import annotations

import secrets
import threading
from collections.abc import Callable
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any, Final

from belvedere.msgs import GamepadState, gamepad_from_json

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
function poll() {
  const pads = Array.from(navigator.getGamepads ? navigator.getGamepads() : []).filter(p => p);
  if (pads.length) {
    const pad = pads[0];
    document.getElementById("status").textContent = "Gamepad: " + pad.id;
    const state = JSON.stringify({
      id: String(pad.id),
      axes: Array.from(pad.axes),
      buttons: Array.from(pad.buttons).map(b => (b.pressed ? 1 : 0)),
    });
    if (state !== last) {
      last = state;
      fetch("state?secret=__SECRET__", {method: "POST", body: state,
        headers: {"Content-Type": "application/json"}});
    }
  }
}
setInterval(poll, period);
</script></body></html>
"""


class JoyPage:
    """The page on ``host:port``; ``on_state(state)`` (on the server's thread) for each state
    it sends."""

    def __init__(
        self,
        on_state: Callable[[GamepadState], None],
        *,
        host: str = "127.0.0.1",
        port: int = 8093,
        poll_hz: float = 50.0,
    ) -> None:
        self.secret = secrets.token_urlsafe(16)
        self.received = 0
        page = _PAGE.replace("__PERIOD__", str(max(1, round(1000 / poll_hz)))).replace(
            "__SECRET__", self.secret
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
                told = self.headers.get("Content-Length") or "0"
                length = int(told) if told.isdigit() else 0
                if not 0 < length <= _MAX_BODY:
                    self.send_error(413)
                    return
                state = gamepad_from_json(self.rfile.read(length))
                if state is None:
                    self.send_error(400)
                    return
                owner.received += 1
                on_state(state)
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
