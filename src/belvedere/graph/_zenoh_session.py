"""The graph's Zenoh network: domains, endpoints, sessions and the key layout.

Graphs have an identity, as ``ROS_DOMAIN_ID`` gives ROS 2's: a domain number ``d`` from 0 to
232 (``BELVEDERE_DOMAIN``, ``--domain``; default 0). Domain ``d`` meets on the endpoint
``tcp/127.0.0.1:<7450 + d>`` (7450 … 7682: TCP, below the ephemeral range, clear of Zenoh's
own 7447; ROS 2's DDS uses UDP) and keeps every key under ``bv/<d>/``, so two domains stay
apart even when ``BELVEDERE_ENDPOINT``/``--endpoint`` points them at one endpoint.

Default: localhost only, no scouting. The first process of a domain listens on its endpoint;
later ones connect to it. Opening to other machines is explicit and guarded by a token
(``--listen``/``--connect``, :mod:`belvedere.graph._hosts`).

Key expressions (under ``bv/<d>``): ``t/<topic>`` data; ``l/<topic>`` each latching
publisher's last message; ``s/<service>`` service calls; ``p`` parameters; liveliness tokens
under ``g/…`` say which node publishes, subscribes or serves what, with which type, and which
process (pid, host) holds each node since when.
"""

from __future__ import annotations

import json
import os
import socket
import threading
from typing import Any, Final

import zenoh

from belvedere.errors import BelvedereError
from belvedere.graph._graph import Graph
from belvedere.graph._hosts import HostAccess

__all__ = [
    "DEFAULT_ENDPOINT",
    "MAX_DOMAIN",
    "TransportError",
    "check_domain",
    "decode_key",
    "domain_endpoint",
    "encode_key",
    "graph_running",
    "open_session",
]

BASE_PORT: Final = 7450
"""Domain ``d`` listens on ``BASE_PORT + d``."""
MAX_DOMAIN: Final = 232
"""The highest domain (as ROS 2's ``ROS_DOMAIN_ID``)."""
DEFAULT_ENDPOINT: Final = f"tcp/127.0.0.1:{BASE_PORT}"
"""Domain 0's endpoint."""


class TransportError(BelvedereError):
    """The transport could not start, or a remote call failed."""


def check_domain(value: int | str | None = None) -> int:
    """The graph domain: ``value``, else ``BELVEDERE_DOMAIN``, else 0 — a whole number from
    0 to :data:`MAX_DOMAIN`."""
    where = "domain"
    if value is None:
        value = os.environ.get("BELVEDERE_DOMAIN", "").strip() or 0
        where = "BELVEDERE_DOMAIN"
    try:
        domain = int(value)
    except ValueError:
        domain = -1
    if not 0 <= domain <= MAX_DOMAIN:
        msg = f"{where} {value!r} is not a graph domain (a whole number from 0 to {MAX_DOMAIN})"
        raise TransportError(msg)
    return domain


def domain_endpoint(domain: int) -> str:
    """Where domain ``domain`` meets: ``tcp/127.0.0.1:<7450 + domain>``."""
    return f"tcp/127.0.0.1:{BASE_PORT + domain}"


def encode_key(name: str) -> str:
    """One key-expression chunk for a graph name or type (``/a/b`` → ``%a%b``)."""
    return name.replace("/", "%") or "%"


def decode_key(chunk: str) -> str:
    return chunk.replace("%", "/")


def graph_running(endpoint: str | None = None, domain: int | None = None) -> bool:
    """Is a graph already listening on the endpoint (``--endpoint``/``--domain``'s, else the
    environment's)? Only TCP (and TLS) endpoints can be asked; others count as not running."""
    if endpoint is None:
        endpoint = HostAccess.from_environment().endpoint(
            None, domain_endpoint(check_domain(domain))
        )
    proto, _, where = endpoint.partition("/")
    host, _, port = where.rpartition(":")
    if proto not in ("tcp", "tls") or not port.isdigit():  # TLS runs over TCP
        return False
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=0.5):
            return True
    except OSError:
        return False


def _config(mode: str, *, listen: str | None, connect: str | None) -> zenoh.Config:
    conf = zenoh.Config()
    conf.insert_json5("mode", json.dumps(mode))
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("scouting/gossip/enabled", "false")
    conf.insert_json5("listen/endpoints", json.dumps([listen] if listen else []))
    conf.insert_json5("connect/endpoints", json.dumps([connect] if connect else []))
    return conf


def open_session(endpoint: str | None = None, *, role: str = "auto") -> tuple[zenoh.Session, str]:
    """Open a session: listen on the endpoint if it is free (``auto``/``listen``), else
    connect to whoever listens there (``auto``/``connect``). Returns (session, role taken).

    A graph open to other hosts (:mod:`belvedere.graph._hosts`) authenticates every session
    with its token; ``BELVEDERE_CONNECT``'s endpoint is only connected to."""
    access = HostAccess.from_environment()
    endpoint = access.endpoint(endpoint, domain_endpoint(check_domain()))
    token = access.guard(endpoint)
    if role == "auto" and access.connect is not None and endpoint == access.connect:
        role = "connect"
    errors = []
    if role in ("auto", "listen"):
        conf = _config("peer", listen=endpoint, connect=None)
        access.configure(conf, endpoint, token)
        try:
            return zenoh.open(conf), "listen"
        except zenoh.ZError as err:
            errors.append(str(err).split(" at ")[0])
    if role in ("auto", "connect"):
        conf = _config("client", listen=None, connect=endpoint)
        access.configure(conf, endpoint, token)
        try:
            return zenoh.open(conf), "connect"
        except zenoh.ZError as err:
            errors.append(str(err).split(" at ")[0])
            if graph_running(endpoint):
                # it accepts connections but not this session: Zenoh's authentication said no
                msg = f"the graph at {endpoint} refused this process: its token is " + (
                    "wrong (or the graph speaks tls/ where this process speaks tcp/, or the "
                    "other way round)"
                    if token
                    else "missing"
                )
                raise TransportError(
                    msg,
                    hint="set BELVEDERE_TOKEN (or --token) to the token the listening host printed",
                ) from None
    msg = f"cannot open the transport on {endpoint}: {'; '.join(errors)}"
    raise TransportError(
        msg, hint="use another domain (--domain N), or --endpoint with a free port"
    )


class _Peer:
    """A process's place on the graph's Zenoh network, which the parts of the transport share:
    its session, its domain's keys and its liveliness tokens (set by
    :class:`~belvedere.graph.ZenohTransport`)."""

    session: zenoh.Session
    prefix: str
    graph: Graph | None
    _zid: str
    _tokens: dict[tuple[str, ...], Any]
    _lock: threading.Lock

    def _key(self, kind: str, name: str = "") -> str:
        """``bv/<domain>/<kind><name>`` (graph names start with '/')."""
        return f"{self.prefix}/{kind}{name}"

    def _token(self, *parts: str, extra: tuple[str, ...] = ()) -> None:
        key = tuple(parts)
        if key not in self._tokens:
            chunks = [encode_key(p) for p in parts]
            expr = "/".join([self._key("g"), *chunks, self._zid, *extra])
            self._tokens[key] = self.session.liveliness().declare_token(expr)

    def _drop_token(self, *parts: str) -> None:
        token = self._tokens.pop(tuple(parts), None)
        if token is not None:
            token.undeclare()
