"""Who may use the viewer: its own page, the origins the user allows, and — when it is served
beyond this machine — only someone holding the token of this run.

A browser lets any web page open a websocket to any address, sending the page's ``Origin``;
the server must refuse. So a websocket handshake is refused (HTTP 403) when its ``Origin`` is
neither the viewer's own page nor one given with ``--allow-origin``. A loopback viewer also
refuses a ``Host`` that is not this machine's name, so a DNS-rebound page cannot pass for its
own origin. A viewer on another address (``--host 0.0.0.0``) also needs the run's token, as
Jupyter does: the URL the CLI prints carries ``?token=…``; the page it loads sets a cookie, so
the websocket that page opens carries the token too.
"""

from __future__ import annotations

import contextlib
import http
import ipaddress
import secrets
import threading
from collections.abc import Callable, Iterable, Iterator
from http.cookies import SimpleCookie
from typing import Any
from urllib.parse import parse_qs, urlsplit

from belvedere.errors import BelvedereError

__all__ = ["ViewerAccess", "ViewerError", "check_origin", "guard_viser", "is_loopback"]

ProcessRequest = Callable[[Any, Any], Any]
"""websockets' ``process_request(connection, request) -> Response | None``."""


class ViewerError(BelvedereError):
    """The viewer could not be set up as asked."""


def is_loopback(host: str) -> bool:
    """Is ``host`` an address only this machine reaches (``127.0.0.1``, ``::1``,
    ``localhost``)?"""
    name = host.strip("[]").lower()
    if name == "localhost" or name.endswith(".localhost"):
        return True
    try:
        return ipaddress.ip_address(name).is_loopback
    except ValueError:
        return False


_DEFAULT_PORTS = {"http": 80, "https": 443}


def _origin(scheme: str, netloc: str) -> str:
    """``scheme://host[:port]`` as browsers send it: lower case, no default port."""
    host, port = netloc.lower(), None
    head, sep, tail = host.rpartition(":")
    if sep and tail.isdigit() and not head.endswith(":"):
        host, port = head, int(tail)
    if port is not None and port != _DEFAULT_PORTS.get(scheme):
        host = f"{host}:{port}"
    return f"{scheme}://{host}"


def check_origin(text: str) -> str:
    """An origin a user allows (``http://localhost:3000``, or ``*`` for any), normalised.

    Raises:
        ViewerError: not ``http(s)://host[:port]``.
    """
    if text.strip() == "*":
        return "*"
    parts = urlsplit(text.strip())
    if (
        parts.scheme not in _DEFAULT_PORTS
        or not parts.netloc
        or parts.path not in ("", "/")
        or parts.query
        or parts.fragment
        or "@" in parts.netloc
    ):
        msg = (
            f"origin {text!r} is not scheme://host[:port] "
            "(e.g. http://localhost:3000, https://example.org; * allows any)"
        )
        raise ViewerError(msg)
    return _origin(parts.scheme, parts.netloc)


class ViewerAccess:
    """The rules one viewer applies to every request it gets."""

    def __init__(
        self, host: str, *, allow_origins: Iterable[str] = (), token: str | None = None
    ) -> None:
        """``token``: None makes one when ``host`` is not loopback (and none when it is)."""
        self.loopback = is_loopback(host)
        self.allow_origins = frozenset(check_origin(o) for o in allow_origins)
        self.token = token if token is not None or self.loopback else secrets.token_urlsafe(24)
        self.installed = False
        """Set once a server applies these rules (see :func:`guard_viser`)."""

    # --- the rules -----------------------------------------------------------------------------
    def refusal(self, headers: Any, path: str, *, port: int) -> str | None:
        """Why a request is refused, or None. ``headers``: the request's (``.get(name)``)."""
        if self.token is not None and not self._has_token(headers, path, port):
            return (
                "this viewer needs its token: open the URL belvedere printed "
                "(http://HOST:PORT/?token=…)"
            )
        if (headers.get("Upgrade") or "").lower() != "websocket":
            return None  # the page itself: a browser sends no Origin for it
        origin = headers.get("Origin")
        if origin is None:
            return None  # not a browser: no page of anyone's is behind it
        try:
            wanted = check_origin(origin)
        except ViewerError:
            return f"origin {origin!r} is not allowed"
        if wanted in self.allow_origins or "*" in self.allow_origins:
            return None
        host = headers.get("Host") or ""
        if wanted not in (_origin("http", host), _origin("https", host)):
            return (
                f"origin {origin} is not allowed (only the viewer's own page"
                + (f" and {', '.join(sorted(self.allow_origins))}" if self.allow_origins else "")
                + "; see --allow-origin)"
            )
        if self.loopback and not is_loopback(urlsplit(f"//{host}").hostname or ""):
            return f"host {host!r} is not this machine"
        return None

    def cookie_name(self, port: int) -> str:
        return f"belvedere-viewer-{port}"

    def _has_token(self, headers: Any, path: str, port: int) -> bool:
        assert self.token is not None
        given = parse_qs(urlsplit(path).query).get("token", [])
        cookie: SimpleCookie = SimpleCookie()
        with contextlib.suppress(Exception):  # a malformed cookie header is no token
            cookie.load(headers.get("Cookie") or "")
        morsel = cookie.get(self.cookie_name(port))
        if morsel is not None:
            given.append(morsel.value)
        return any(secrets.compare_digest(g.encode(), self.token.encode()) for g in given)

    # --- the hook into the server --------------------------------------------------------------
    def wrap(self, inner: ProcessRequest | None, port: int) -> ProcessRequest:
        """``inner`` (viser's page server), with these rules applied first."""

        def process_request(connection: Any, request: Any) -> Any:
            reason = self.refusal(request.headers, request.path, port=port)
            if reason is not None:
                return connection.respond(http.HTTPStatus.FORBIDDEN, reason + "\n")
            response = inner(connection, request) if inner is not None else None
            if response is not None and self.token is not None and response.status_code == 200:
                # The page's own websocket then carries the token (its URL has no query).
                response.headers["Set-Cookie"] = (
                    f"{self.cookie_name(port)}={self.token}; Path=/; HttpOnly; SameSite=Strict"
                )
            return response

        self.installed = True
        return process_request


_SERVE_LOCK = threading.Lock()


@contextlib.contextmanager
def guard_viser(access: ViewerAccess) -> Iterator[None]:
    """While a ``viser.ViserServer`` is being made, give its server ``access``'s rules.

    viser offers no hook to check a request before the websocket handshake: its server is
    ``websockets.asyncio.server.serve(…, process_request=<its page server>)``, called in its
    own thread and waited for inside ``ViserServer()``. So for that call only we stand in for
    ``serve`` and wrap the ``process_request`` it is given, which is websockets' own place to
    refuse a handshake with an HTTP response. (Wrapping the server instead means a proxy in
    front of it, a second hop for every message; subclassing means copying its 300-line
    server loop.) The caller checks :attr:`ViewerAccess.installed` afterwards, so a viser
    that serves differently is refused rather than served open.
    """
    import websockets.asyncio.server as ws_server

    original = ws_server.serve

    def serve(*args: Any, **kwargs: Any) -> Any:
        port = kwargs.get("port", args[2] if len(args) > 2 else 0)
        kwargs["process_request"] = access.wrap(kwargs.get("process_request"), int(port))
        return original(*args, **kwargs)

    with _SERVE_LOCK:
        setattr(ws_server, "serve", serve)  # noqa: B010 (mypy: a function for a class)
        try:
            yield
        finally:
            setattr(ws_server, "serve", original)  # noqa: B010
