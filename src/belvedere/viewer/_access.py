"""Who may use the viewer: its own page, the origins the user allows, and — served beyond this
machine — only someone holding this run's token (the rules are :mod:`belvedere.access`'s);
and how they are put into viser's server, which has no hook of its own."""

from __future__ import annotations

import contextlib
import io
import logging
import threading
from collections.abc import Iterable, Iterator
from typing import Any

from belvedere.access import ServerAccess
from belvedere.errors import BelvedereError

__all__ = ["ViewerError", "guard_viser", "page_url", "serve_viser", "viewer_access"]

logger = logging.getLogger(__name__)


class ViewerError(BelvedereError):
    """The viewer could not be set up as asked."""


def viewer_access(
    host: str, *, allow_origins: Iterable[str] = (), token: str | None = None
) -> ServerAccess:
    """The viewer's rules: its own page and ``allow_origins``; a token off loopback."""
    return ServerAccess(
        host, what="viewer", allow_origins=allow_origins, own_page=True, token=token
    )


_SERVE_LOCK = threading.Lock()


@contextlib.contextmanager
def guard_viser(access: ServerAccess) -> Iterator[None]:
    """While a ``viser.ViserServer`` is being made, give its server ``access``'s rules.

    viser offers no hook to check a request before the websocket handshake: its server is
    ``websockets.asyncio.server.serve(…, process_request=<its page server>)``, called in its
    own thread and waited for inside ``ViserServer()``. So for that call only we stand in for
    ``serve`` and wrap the ``process_request`` it is given, which is websockets' own place to
    refuse a handshake with an HTTP response. (Wrapping the server instead means a proxy in
    front of it, a second hop for every message; subclassing means copying its 300-line
    server loop.) The caller checks :attr:`ServerAccess.installed` afterwards, so a viser
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


def serve_viser(access: ServerAccess, host: str, port: int) -> Any:
    """A ``viser.ViserServer`` on ``host:port`` under ``access``'s rules.

    Raises:
        ViewerError: this viser serves its page in a way the rules cannot be put into.
    """
    import viser  # heavy: only the browser pages use it

    # viser prints a banner on stdout whatever ``verbose`` says: stdout is for data (the
    # URL, echoed messages), and the banner's URL lacks the token.
    with guard_viser(access), contextlib.redirect_stdout(io.StringIO()):
        server = viser.ViserServer(host=host, port=port, verbose=False)
    if port and server.get_port() != port:
        # viser quietly takes the next free port: a user opening the one they asked for
        # would find another program (or an older viewer) there
        logger.warning(
            "viewer: port %d is taken; serving on port %d instead", port, server.get_port()
        )
    if not access.installed:
        server.stop()
        msg = (
            f"viser {viser.__version__} serves its page in a way belvedere cannot guard "
            "(the origin and token checks were not installed); not serving the viewer"
        )
        raise ViewerError(msg)
    return server


def page_url(server: Any, access: ServerAccess) -> str:
    """Where to open a viser ``server``'s page (with ``?token=…`` when it needs one)."""
    base = f"http://{server.get_host()}:{server.get_port()}"
    return f"{base}/?token={access.token}" if access.token else base
