"""Who may use a server belvedere runs (the viewer, the Foxglove bridge): pages of the origins
it trusts, and — when it is served beyond this machine — only someone holding this run's token.

A browser lets any web page open a websocket to any address, sending the page's ``Origin``;
the server must refuse. So a websocket handshake is refused (HTTP 403) when its ``Origin`` is
none the server trusts: its own page (the viewer), a page of this machine (the Foxglove
bridge: a tool of the user's own on localhost), the origins a server trusts by default
(Foxglove's web app) and those given with ``--allow-origin``. A handshake without ``Origin``
does not come from a web page (a desktop app, a script) and passes. A loopback server also
refuses a ``Host`` that is not this machine's name, so a DNS-rebound page cannot pass for a
trusted origin. A server on another address (``--host 0.0.0.0``) also needs the run's token,
as Jupyter does: the URL printed carries ``?token=…``; a page the server serves sets a cookie,
so the websocket that page opens carries the token too.
"""

from __future__ import annotations

import contextlib
import http
import ipaddress
import secrets
from collections.abc import Callable, Iterable
from http.cookies import SimpleCookie
from typing import Any
from urllib.parse import parse_qs, urlsplit

from belvedere.errors import BelvedereError

__all__ = ["AccessError", "ServerAccess", "check_origin", "is_loopback"]

ProcessRequest = Callable[[Any, Any], Any]
"""websockets' ``process_request(connection, request) -> Response | None``."""


class AccessError(BelvedereError):
    """An origin or an address a server cannot be given."""


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
        AccessError: not ``http(s)://host[:port]``.
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
        raise AccessError(msg)
    return _origin(parts.scheme, parts.netloc)


class ServerAccess:
    """The rules one server applies to every request it gets.

    ``what`` names the server in refusals (``viewer``); ``own_page``: the server's own page
    (an origin equal to the request's ``Host``) may connect; ``local_pages``: any page of
    this machine (an origin whose host is loopback) may connect; ``default_origins``: trusted
    besides those the user allows.
    """

    def __init__(
        self,
        host: str,
        *,
        what: str = "server",
        allow_origins: Iterable[str] = (),
        default_origins: Iterable[str] = (),
        own_page: bool = False,
        local_pages: bool = False,
        token: str | None = None,
    ) -> None:
        """``token``: None makes one when ``host`` is not loopback (and none when it is)."""
        self.what = what
        self.loopback = is_loopback(host)
        self.allow_origins = frozenset(check_origin(o) for o in allow_origins)
        self.default_origins = frozenset(check_origin(o) for o in default_origins)
        self.own_page = own_page
        self.local_pages = local_pages
        self.token = token if token is not None or self.loopback else secrets.token_urlsafe(24)
        self.installed = False
        """Set once a server applies these rules (see :meth:`wrap`)."""

    # --- the rules -----------------------------------------------------------------------------
    def refusal(self, headers: Any, path: str, *, port: int) -> str | None:
        """Why a request is refused, or None. ``headers``: the request's (``.get(name)``)."""
        if self.token is not None and not self._has_token(headers, path, port):
            return f"this {self.what} needs its token: use the URL belvedere printed (…/?token=…)"
        if (headers.get("Upgrade") or "").lower() != "websocket":
            return None  # a page itself: a browser sends no Origin for it
        origin = headers.get("Origin")
        if origin is None:
            return None  # not a browser: no page of anyone's is behind it
        try:
            wanted = check_origin(origin)
        except AccessError:
            return f"origin {origin!r} is not allowed"
        host = headers.get("Host") or ""
        if self.loopback and not is_loopback(urlsplit(f"//{host}").hostname or ""):
            return f"host {host!r} is not this machine"
        trusted = self.allow_origins | self.default_origins
        if wanted in trusted or "*" in self.allow_origins:
            return None
        if self.own_page and wanted in (_origin("http", host), _origin("https", host)):
            return None
        if self.local_pages and is_loopback(urlsplit(wanted).hostname or ""):
            return None
        return f"origin {origin} is not allowed (only {self._trusted_text()}; see --allow-origin)"

    def _trusted_text(self) -> str:
        kinds = []
        if self.own_page:
            kinds.append(f"the {self.what}'s own page")
        if self.local_pages:
            kinds.append("pages of this machine")
        kinds.extend(sorted(self.default_origins | self.allow_origins))
        if not kinds:
            return "clients that are not web pages"
        return ", ".join(kinds[:-1]) + (" and " if len(kinds) > 1 else "") + kinds[-1]

    def cookie_name(self, port: int) -> str:
        return f"belvedere-{self.what.replace(' ', '-')}-{port}"

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
        """websockets' ``process_request``: these rules, then ``inner`` (a page server)."""

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
