"""A live picture as a page of belvedere's own on 127.0.0.1: the page asks for the picture
(an SVG laid out by ``dot``) every second with its controls' choices, so it follows the graph
as nodes come and go. Every request passes :mod:`belvedere.access`'s rules."""

from __future__ import annotations

import html
import threading
from collections.abc import Callable
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from urllib.parse import parse_qs, urlsplit

from belvedere.access import ServerAccess, is_loopback
from belvedere.errors import BelvedereError
from belvedere.pictures._dot import render

__all__ = ["Draw", "PicturePage"]

Draw = Callable[[dict[str, list[str]]], str]
"""The picture (Graphviz's language) for the page's query (its controls' choices)."""

REFRESH_MS = 1000

_PAGE = """<!doctype html>
<html><head><meta charset="utf-8"><title>{title}</title>
<style>
body {{ font-family: sans-serif; margin: 0; background: #fff; }}
header {{ padding: 6px 10px; background: #eee; border-bottom: 1px solid #ccc; }}
header label {{ margin-right: 12px; }}
#picture {{ padding: 8px; overflow: auto; }}
#picture svg {{ max-width: 100%; height: auto; }}
#status {{ color: #a00; }}
</style></head>
<body><header><b>{title}</b> &nbsp; <form id="controls" style="display:inline">{controls}</form>
<label><input type="checkbox" id="pause"> Pause</label> <span id="status"></span></header>
<div id="picture">waiting for the first picture…</div>
<script>
const form = document.getElementById("controls");
async function refresh() {{
  if (!document.getElementById("pause").checked) {{
    const query = new URLSearchParams();
    for (const el of form.elements) {{
      if (el.type === "checkbox") query.set(el.name, el.checked ? "1" : "0");
      else if (el.name) query.set(el.name, el.value);
    }}
    try {{
      const reply = await fetch("picture.svg?" + query.toString(), {{cache: "no-store"}});
      const text = await reply.text();
      if (reply.ok) {{
        document.getElementById("picture").innerHTML = text;
        document.getElementById("status").textContent = "";
      }} else {{
        document.getElementById("status").textContent = text;
      }}
    }} catch (e) {{
      document.getElementById("status").textContent = "the picture's server has gone";
    }}
  }}
  setTimeout(refresh, {refresh});
}}
refresh();
</script></body></html>
"""


class PicturePage:
    """A page showing ``draw``'s picture, served on ``host``:``port`` (0: a free one) until
    :meth:`close`. ``controls``: the page's form fields (HTML; their names are the query's)."""

    def __init__(
        self,
        title: str,
        draw: Draw,
        *,
        controls: str = "",
        host: str = "127.0.0.1",
        port: int = 0,
    ) -> None:
        self.title = title
        self.draw = draw
        self.access = ServerAccess(host, what=title, own_page=True)
        page = _PAGE.format(title=html.escape(title), controls=controls, refresh=REFRESH_MS)
        handler = _handler(self, page.encode())
        try:
            self._server = ThreadingHTTPServer((host, port), handler)
        except OSError as err:
            msg = f"{title}: cannot serve its page on {host}:{port}: {err.strerror or err}"
            raise BelvedereError(msg) from None
        self._server.daemon_threads = True
        self.port: int = self._server.server_address[1]
        self.url = f"http://{'127.0.0.1' if is_loopback(host) else host}:{self.port}/"
        if self.access.token is not None:
            self.url += f"?token={self.access.token}"
        self.access.installed = True
        self._thread = threading.Thread(
            target=self._server.serve_forever, name=f"belvedere-{title}-page", daemon=True
        )
        self._thread.start()

    def picture(self, query: dict[str, list[str]], fmt: str = "svg") -> bytes:
        return render(self.draw(query), fmt)

    def close(self) -> None:
        self._server.shutdown()
        self._server.server_close()


def _handler(page: PicturePage, body: bytes) -> type[BaseHTTPRequestHandler]:
    class Handler(BaseHTTPRequestHandler):
        def log_message(self, format: str, *args: object) -> None:
            del format, args  # a request a second is no news

        def do_GET(self) -> None:
            reason = page.access.refusal(self.headers, self.path, port=page.port)
            host = urlsplit(f"//{self.headers.get('Host') or ''}").hostname or ""
            if reason is None and page.access.loopback and not is_loopback(host):
                reason = f"host {host!r} is not this machine"  # a DNS-rebound page
            if reason is not None:
                self._send(HTTPStatus.FORBIDDEN, "text/plain", (reason + "\n").encode())
                return
            parts = urlsplit(self.path)
            query = parse_qs(parts.query)
            if parts.path == "/":
                self._send(HTTPStatus.OK, "text/html; charset=utf-8", body)
            elif parts.path in ("/picture.svg", "/picture.gv"):
                try:
                    if parts.path.endswith(".gv"):
                        data, kind = page.draw(query).encode(), "text/plain; charset=utf-8"
                    else:
                        data, kind = page.picture(query), "image/svg+xml"
                except BelvedereError as err:
                    self._send(HTTPStatus.SERVICE_UNAVAILABLE, "text/plain", err.message.encode())
                    return
                self._send(HTTPStatus.OK, kind, data)
            else:
                self._send(HTTPStatus.NOT_FOUND, "text/plain", b"no such page\n")

        def _send(self, status: HTTPStatus, kind: str, data: bytes) -> None:
            self.send_response(status)
            self.send_header("Content-Type", kind)
            self.send_header("Content-Length", str(len(data)))
            self.send_header("Cache-Control", "no-store")
            if page.access.token is not None and status == HTTPStatus.OK:
                name = page.access.cookie_name(page.port)
                self.send_header(
                    "Set-Cookie", f"{name}={page.access.token}; Path=/; HttpOnly; SameSite=Strict"
                )
            self.end_headers()
            self.wfile.write(data)

    return Handler
