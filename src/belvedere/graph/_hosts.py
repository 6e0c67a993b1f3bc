"""One graph across hosts: where a graph meets when it is open to other machines, and the
token that guards it.

By default a graph is loopback only (:mod:`belvedere.graph._zenoh_session`). A host opens
it with ``BELVEDERE_LISTEN=tcp/IP:PORT`` (``--listen``), others join with
``BELVEDERE_CONNECT=tcp/HOST:PORT`` (``--connect``), as ``ROS_MASTER_URI`` names the master;
``BELVEDERE_DISCOVER=1`` (``--discover``) lets Zenoh's multicast scouting find peers on a LAN.

Nothing is open without protection: a graph that listens off loopback, listens by
``--listen`` or scouts needs ``BELVEDERE_TOKEN``, and every Zenoh session of it then
authenticates with Zenoh's user/password scheme (user ``belvedere``, the token as password).
Zenoh checks it by a challenge, so the token never crosses the network, and refuses a peer
without it before any message flows. On a ``tcp/`` endpoint the traffic itself is not
encrypted; on a ``tls/`` endpoint it is, with certificates made from the token
(:mod:`belvedere.graph._tls`).
"""

from __future__ import annotations

import atexit
import contextlib
import ipaddress
import json
import os
import secrets
import tempfile
from dataclasses import dataclass
from typing import Final

import zenoh

from belvedere.errors import BelvedereError
from belvedere.graph._tls import tls_settings

__all__ = [
    "TOKEN_USER",
    "HostAccess",
    "HostAccessError",
    "check_token",
    "endpoint_host",
    "is_loopback_endpoint",
    "new_token",
]

TOKEN_USER: Final = "belvedere"
"""The Zenoh user every process of a guarded graph authenticates as."""

_TOKEN_CHARS: Final = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_")
_MIN_TOKEN: Final = 16


class HostAccessError(BelvedereError):
    """A graph opened to other hosts without what guards it, or a bad endpoint or token."""


def new_token() -> str:
    """A fresh graph token: 32 URL-safe characters (192 bits), never starting with ``-``
    (``--token -x…`` would read as an option: one token in 64 did)."""
    while True:
        token = secrets.token_urlsafe(24)
        if not token.startswith("-"):
            return token


def check_token(token: str, *, where: str = "BELVEDERE_TOKEN") -> str:
    """``token``, if it is one (at least 16 of ``A-Z a-z 0-9 - _``: Zenoh's dictionary file
    is ``user:password`` lines, so nothing else may appear in it)."""
    if len(token) < _MIN_TOKEN or not set(token) <= _TOKEN_CHARS:
        msg = f"{where}: not a graph token (at least {_MIN_TOKEN} of A-Z a-z 0-9 - _)"
        raise HostAccessError(msg, hint="copy the token the listening host printed")
    return token


def endpoint_host(endpoint: str) -> str:
    """The host part of ``tcp/HOST:PORT`` (``[v6]`` unbracketed)."""
    proto, _, where = endpoint.partition("/")
    host, sep, port = where.rpartition(":")
    if proto not in ("tcp", "udp", "tls", "quic") or not sep or not port.isdigit() or not host:
        msg = f"{endpoint!r} is not a graph endpoint (tcp/HOST:PORT)"
        raise HostAccessError(msg, hint="e.g. --listen tcp/192.168.1.10:7450")
    return host.strip("[]")


def is_loopback_endpoint(endpoint: str) -> bool:
    """Does ``endpoint`` stay on this machine (127.0.0.0/8, ::1, ``localhost``)?"""
    host = endpoint_host(endpoint)
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False  # a host name: it may resolve anywhere


@dataclass(frozen=True)
class HostAccess:
    """How this process meets other hosts, from the environment the command line set."""

    listen: str | None = None
    """``BELVEDERE_LISTEN``: the endpoint this graph is opened on."""
    connect: str | None = None
    """``BELVEDERE_CONNECT``: the endpoint of a graph another host opened."""
    token: str | None = None
    """``BELVEDERE_TOKEN``: the graph's token."""
    discover: bool = False
    """``BELVEDERE_DISCOVER``: find peers by Zenoh's multicast scouting."""

    @classmethod
    def from_environment(cls) -> HostAccess:
        env = os.environ
        listen = env.get("BELVEDERE_LISTEN", "").strip() or None
        connect = env.get("BELVEDERE_CONNECT", "").strip() or None
        token = env.get("BELVEDERE_TOKEN", "").strip() or None
        discover = env.get("BELVEDERE_DISCOVER", "").strip().lower() in ("1", "true", "yes")
        for value in (listen, connect):
            if value is not None:
                endpoint_host(value)
        if token is not None:
            check_token(token)
        return cls(listen, connect, token, discover)

    def endpoint(self, given: str | None, domain_endpoint: str) -> str:
        """Where the graph meets: ``given`` (``--endpoint``), else the host it connects to,
        else where it listens, else ``BELVEDERE_ENDPOINT``, else the domain's."""
        return (
            given
            or self.connect
            or self.listen
            or os.environ.get("BELVEDERE_ENDPOINT")
            or domain_endpoint
        )

    def guard(self, endpoint: str) -> str | None:
        """The token a session on ``endpoint`` must authenticate with, or None when it stays
        on loopback unguarded. Raises for a graph that would be open without one."""
        opened = (
            self.discover
            or endpoint.startswith("tls/")  # its certificates come from the token
            or (self.listen is not None and endpoint == self.listen)
            or (self.connect is not None and endpoint == self.connect)  # a --listen graph
            or not is_loopback_endpoint(endpoint)
        )
        if self.token is not None:
            return self.token
        if not opened:
            return None
        if self.connect is not None and endpoint == self.connect:
            msg = f"joining the graph at {endpoint} needs its token"
            hint = "set BELVEDERE_TOKEN (or --token) to the token the listening host printed"
        else:
            msg = f"a graph open to other hosts ({endpoint}) needs a token"
            hint = "use --listen (it makes one), or set BELVEDERE_TOKEN"
        raise HostAccessError(msg, hint=hint)

    def configure(self, conf: zenoh.Config, endpoint: str, token: str | None) -> None:
        """Add scouting, the token's authentication and (on a ``tls/`` endpoint) the
        token's certificates to the ``conf`` of a session on ``endpoint``."""
        if self.discover:
            conf.insert_json5("scouting/multicast/enabled", "true")
        if token is None:
            return
        if endpoint.startswith("tls/"):
            conf.insert_json5("transport/link/tls", json.dumps(tls_settings(token)))
        auth = {"user": TOKEN_USER, "password": token, "dictionary_file": _dictionary(token)}
        conf.insert_json5("transport/auth/usrpwd", json.dumps(auth))


_dictionaries: dict[str, str] = {}


def _dictionary(token: str) -> str:
    """Zenoh reads the accepted ``user:password`` pairs from a file: one per token, readable
    by this user alone, kept for the process's life."""
    path = _dictionaries.get(token)
    if path is None:
        fd, path = tempfile.mkstemp(prefix="belvedere-graph-", suffix=".auth")
        with os.fdopen(fd, "w", encoding="ascii") as out:  # mkstemp: mode 0600
            out.write(f"{TOKEN_USER}:{token}\n")
        _dictionaries[token] = path
        atexit.register(_remove, path)
    return path


def _remove(path: str) -> None:
    with contextlib.suppress(OSError):
        os.unlink(path)
