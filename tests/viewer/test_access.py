"""Who may use the viewer, checked with real websocket handshakes against a real viewer:
its own page, origins the user allows, and the run's token when served beyond loopback."""

from __future__ import annotations

import socket
import subprocess
import sys
import urllib.error
import urllib.request
from collections.abc import Iterator
from typing import Any

import pytest
import viser
import websockets.exceptions
from websockets.sync.client import connect

from belvedere.access import AccessError, ServerAccess, check_origin
from belvedere.cli import main
from belvedere.graph import Graph
from belvedere.viewer import Viewer

PROTOCOL = f"viser-v{viser.__version__}"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


@pytest.fixture
def open_viewer() -> Iterator[Any]:
    made: list[tuple[Graph, Viewer]] = []

    def make(**options: Any) -> Viewer:
        graph = Graph(sim_time=False)
        viewer = Viewer(graph, port=free_port(), **options)
        made.append((graph, viewer))
        return viewer

    yield make
    for graph, viewer in made:
        viewer.close()
        graph.shutdown()


def handshake(port: int, *, path: str = "/", origin: str | None, **headers: str) -> bytes:
    """Open the viewer's websocket as a browser would; returns its first message."""
    with connect(
        f"ws://127.0.0.1:{port}{path}",
        origin=origin,  # type: ignore[arg-type]
        subprotocols=[PROTOCOL],  # type: ignore[list-item]
        additional_headers=headers,
        open_timeout=10,
    ) as ws:
        message = ws.recv(timeout=10)
        assert isinstance(message, bytes)
        return message


def refused(port: int, *, path: str = "/", origin: str | None, **headers: str) -> str:
    """The handshake is refused with HTTP 403: returns the reason given."""
    with pytest.raises(websockets.exceptions.InvalidStatus) as caught:
        handshake(port, path=path, origin=origin, **headers)
    response = caught.value.response
    assert response.status_code == 403
    return response.body.decode()


def test_the_viewers_own_page_is_accepted_and_any_other_refused(open_viewer: Any) -> None:
    viewer = open_viewer()
    port = viewer.server.get_port()
    assert viewer.url == f"http://127.0.0.1:{port}"  # loopback: no token
    assert handshake(port, origin=f"http://127.0.0.1:{port}")
    assert handshake(port, origin=None)  # not a browser: no page behind it
    reason = refused(port, origin="http://evil.example")
    assert reason == (
        "origin http://evil.example is not allowed (only the viewer's own page; "
        "see --allow-origin)\n"
    )
    assert "not allowed" in refused(port, origin=f"http://127.0.0.1:{port + 1}")
    assert "not allowed" in refused(port, origin="null")  # a sandboxed frame or a file


def test_a_dns_rebound_page_is_refused(open_viewer: Any) -> None:
    """A page on evil.example that re-resolves to 127.0.0.1 sends its own name as Host and
    Origin: the same origin, but not this machine's name."""
    port = open_viewer().server.get_port()
    with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
        s.sendall(
            (
                "GET / HTTP/1.1\r\n"
                f"Host: evil.example:{port}\r\n"
                f"Origin: http://evil.example:{port}\r\n"
                "Upgrade: websocket\r\nConnection: Upgrade\r\n"
                "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
                f"Sec-WebSocket-Protocol: {PROTOCOL}\r\n\r\n"
            ).encode()
        )
        answer = s.recv(4096).decode()
    assert answer.startswith("HTTP/1.1 403 Forbidden\r\n")
    assert answer.endswith(f"host 'evil.example:{port}' is not this machine\n")


def test_allowed_origins_are_accepted(open_viewer: Any) -> None:
    viewer = open_viewer(allow_origins=["http://localhost:3000", "HTTPS://Example.org:443/"])
    port = viewer.server.get_port()
    assert handshake(port, origin="http://localhost:3000")
    assert handshake(port, origin="https://example.org")
    reason = refused(port, origin="http://localhost:3001")
    assert reason == (
        "origin http://localhost:3001 is not allowed (only the viewer's own page, "
        "http://localhost:3000 and https://example.org; see --allow-origin)\n"
    )
    anyone = open_viewer(allow_origins=["*"])
    assert handshake(anyone.server.get_port(), origin="http://evil.example")


def test_beyond_loopback_the_token_is_required(open_viewer: Any) -> None:
    viewer = open_viewer(host="0.0.0.0")  # reached here only through 127.0.0.1
    port = viewer.server.get_port()
    token = viewer.access.token
    assert token is not None
    assert len(token) >= 32
    assert viewer.url == f"http://0.0.0.0:{port}/?token={token}"
    own = f"http://127.0.0.1:{port}"
    assert "needs its token" in refused(port, origin=own)
    assert "needs its token" in refused(port, path="/?token=wrong", origin=own)
    assert "needs its token" in refused(port, path="/?token=", origin=own)
    assert handshake(port, path=f"/?token={token}", origin=own)
    # The right token does not make a foreign page welcome.
    assert "not allowed" in refused(port, path=f"/?token={token}", origin="http://evil.example")
    # Another run has another token.
    assert open_viewer(host="0.0.0.0").access.token != token


def test_the_page_with_the_token_lets_its_websocket_in_by_cookie(open_viewer: Any) -> None:
    """The browser's path: the printed URL loads the page, which sets a cookie; the page's
    websocket URL has no query, and the cookie carries the token."""
    viewer = open_viewer(host="0.0.0.0")
    port = viewer.server.get_port()
    with pytest.raises(urllib.error.HTTPError) as no_token:
        urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=10)
    assert no_token.value.code == 403
    with urllib.request.urlopen(
        f"http://127.0.0.1:{port}/?token={viewer.access.token}", timeout=10
    ) as page:
        assert page.status == 200
        assert b"<html" in page.read()[:2000].lower()
        cookie = page.headers["Set-Cookie"]
    assert cookie == (
        f"belvedere-viewer-{port}={viewer.access.token}; Path=/; HttpOnly; SameSite=Strict"
    )
    own = f"http://127.0.0.1:{port}"
    assert handshake(port, origin=own, Cookie=cookie.split(";")[0])
    wrong = f"belvedere-viewer-{port}=x; belvedere-viewer-{port + 1}={viewer.access.token}"
    assert "needs its token" in refused(port, origin=own, Cookie=wrong)


def test_access_rules_without_a_server() -> None:
    assert ServerAccess("127.0.0.1").token is None
    assert ServerAccess("localhost").token is None
    assert ServerAccess("::1").token is None
    assert ServerAccess("0.0.0.0").token is not None
    assert ServerAccess("192.0.2.7").token is not None
    assert ServerAccess("127.0.0.1", token="given").token == "given"
    assert check_origin("http://LOCALHOST:80") == "http://localhost"
    assert check_origin("http://[::1]:8080/") == "http://[::1]:8080"
    for bad in ("localhost:3000", "ftp://x", "http://x/path", "http://user@x", ""):
        with pytest.raises(AccessError, match=r"is not scheme://host\[:port\]"):
            check_origin(bad)


def test_allow_origin_on_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    for verb in ("display", "sim", "launch"):
        assert main([verb, "x", "--allow-origin", "localhost:3000"]) == 2
        err = capsys.readouterr().err
        assert "argument --allow-origin: origin 'localhost:3000' is not scheme://host" in err


MBOT = "examples/mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"


def test_display_prints_the_url_with_its_token() -> None:
    port = free_port()
    proc = subprocess.Popen(
        [
            *(sys.executable, "-m", "belvedere", "display", MBOT),
            *("--host", "0.0.0.0", "--port", str(port), "--duration", "60"),
            *("--allow-origin", "http://localhost:3000"),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert proc.stdout is not None
        url = proc.stdout.readline().strip()
        prefix = f"http://0.0.0.0:{port}/?token="
        assert url.startswith(prefix)
        token = url.removeprefix(prefix)
        assert "needs its token" in refused(port, origin="http://localhost:3000")
        assert handshake(port, path=f"/?token={token}", origin="http://localhost:3000")
    finally:
        proc.terminate()
        proc.wait(timeout=20)
