"""The WebSocket server of the Foxglove protocol: handshakes checked, clients served, each
client's input refused to that client alone.

It runs an asyncio loop on a thread of its own (websockets' server). Other threads hand it
channels, messages and the time through thread-safe methods; its listener (the bridge) is
told what clients ask. A handshake passes :class:`~belvedere.access.ServerAccess`'s rules
(origin, host, and the token off loopback) or gets HTTP 403. Every frame a client sends is
parsed by :mod:`._protocol`; a refusal is an error status to that client, and an error in
the listener is logged and told to that client — the server and the other clients go on.

Each client has two queues: control messages (advertisements, statuses, parameters), never
dropped — a client that lets :data:`CONTROL_BACKLOG` of them pile up is disconnected, as
too slow to serve — and data (message and time frames), where the oldest is dropped past
:data:`DATA_BACKLOG`, as a ROS subscriber's full queue drops.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import logging
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, Final, Protocol

from belvedere.access import ServerAccess
from belvedere.foxglove import _protocol as wire
from belvedere.foxglove._protocol import ProtocolError

__all__ = [
    "CONTROL_BACKLOG",
    "DATA_BACKLOG",
    "MAX_CLIENT_CHANNELS",
    "MAX_FRAME_BYTES",
    "ChannelInfo",
    "Listener",
    "Server",
    "StatusLevel",
]

logger = logging.getLogger("belvedere.foxglove")

MAX_FRAME_BYTES: Final = 64 << 20
"""A client frame's size (a camera image published from the app is a few MiB)."""
DATA_BACKLOG: Final = 1024
CONTROL_BACKLOG: Final = 4096
MAX_CLIENT_CHANNELS: Final = 1000
"""Channels one client may advertise at once."""
MAX_LISTED: Final = 10
"""Refusals named in one status (one request can hold thousands of bad items)."""
PARAMETER_POLL_S: Final = 0.5
"""Wall seconds between looks at the parameters while a client follows some."""


class StatusLevel:
    INFO: Final = 0
    WARNING: Final = 1
    ERROR: Final = 2


@dataclass(frozen=True, slots=True)
class ChannelInfo:
    """A channel as advertised."""

    id: int
    topic: str
    encoding: str
    schema_name: str
    schema: str
    schema_encoding: str

    def advertisement(self) -> dict[str, Any]:
        return {
            "id": self.id,
            "topic": self.topic,
            "encoding": self.encoding,
            "schemaName": self.schema_name,
            "schemaEncoding": self.schema_encoding,
            "schema": self.schema,
        }


class Listener(Protocol):
    """What the server tells its owner. The ``on_*`` methods run on the server's loop and must
    not block; the parameter methods run on a worker thread. A :class:`ProtocolError` raised
    by any of them goes back to the client as an error status."""

    def on_subscribe(self, client: int, channel: int) -> None: ...

    def on_unsubscribe(self, client: int, channel: int) -> None: ...

    def on_client_advertise(self, client: int, channel: wire.ClientChannel) -> None: ...

    def on_client_unadvertise(self, client: int, channel: int) -> None: ...

    def on_client_message(self, client: int, channel: int, data: bytes) -> None: ...

    def get_parameters(self, names: Sequence[str]) -> list[dict[str, Any]]: ...

    def set_parameters(
        self, parameters: Sequence[tuple[str, Any]]
    ) -> tuple[list[dict[str, Any]], list[str]]:
        """The values now, and why each refused one was refused."""


@dataclass(eq=False)
class _Client:
    id: int
    ws: Any
    address: str
    subscriptions: dict[int, int] = field(default_factory=dict)
    """Subscription id -> channel id."""
    by_channel: dict[int, int] = field(default_factory=dict)
    """Channel id -> subscription id."""
    client_channels: set[int] = field(default_factory=set)
    parameters: set[str] | None = None
    """Parameters it follows (None: none; an empty set: all)."""
    control: deque[str | bytes] = field(default_factory=deque)
    data: deque[bytes] = field(default_factory=lambda: deque(maxlen=DATA_BACKLOG))
    wake: asyncio.Event = field(default_factory=asyncio.Event)
    dropped: int = 0
    closing: bool = False


class Server:
    """Serves the protocol on ``host:port`` (0: any free port) under ``access``'s rules."""

    def __init__(
        self,
        listener: Listener,
        *,
        host: str,
        port: int,
        access: ServerAccess,
        name: str,
        capabilities: Sequence[str],
        encodings: Sequence[str],
    ) -> None:
        """Raises OSError when the address cannot be served (the port is taken)."""
        import websockets.asyncio.server as ws_server

        self.listener = listener
        self.access = access
        self._info = wire.text(
            "serverInfo",
            name=name,
            capabilities=list(capabilities),
            supportedEncodings=list(encodings),
            metadata={"library": "belvedere"},
            sessionId=str(time.time_ns() // 1_000_000),
        )
        self._channels: dict[int, ChannelInfo] = {}
        self._clients: dict[int, _Client] = {}
        self._ids = itertools.count(1)
        self._parameters: dict[str, Any] = {}
        """The last values clients following parameters were told (loop thread)."""
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(
            target=self._loop.run_forever, name="belvedere-foxglove-ws", daemon=True
        )
        self._thread.start()

        async def start() -> Any:
            return await ws_server.serve(
                self._serve,
                host,
                port,
                subprotocols=[wire.SUBPROTOCOLS[0], wire.SUBPROTOCOLS[1]],  # type: ignore[list-item]
                process_request=access.wrap(None, port),
                max_size=MAX_FRAME_BYTES,
                max_queue=4,
                compression=None,
                server_header=None,
            )

        try:
            self._server = asyncio.run_coroutine_threadsafe(start(), self._loop).result()
        except BaseException:
            self._stop_loop()
            raise
        self.port: int = self._server.sockets[0].getsockname()[1]
        self._poller = asyncio.run_coroutine_threadsafe(self._poll_parameters(), self._loop)

    # --- from other threads --------------------------------------------------------------------
    def stop(self) -> None:
        """Close every connection and the listening socket."""
        if not self._loop.is_running():
            return

        async def close() -> None:
            self._poller.cancel()
            self._server.close()
            await self._server.wait_closed()

        with contextlib.suppress(Exception):  # closing: nothing is left to tell
            asyncio.run_coroutine_threadsafe(close(), self._loop).result(timeout=5.0)
        self._stop_loop()

    def _stop_loop(self) -> None:
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join(timeout=5.0)
        if not self._loop.is_running():
            self._loop.close()

    def _call(self, fn: Callable[..., None], *args: Any) -> None:
        with contextlib.suppress(RuntimeError):  # the loop closed: the server stopped
            self._loop.call_soon_threadsafe(fn, *args)

    def add_channel(self, channel: ChannelInfo) -> None:
        self._call(self._add_channel, channel)

    def remove_channel(self, channel: int) -> None:
        self._call(self._remove_channel, channel)

    def log(self, batch: list[tuple[int, int, bytes]]) -> None:
        """(channel id, log time ns, serialized message) of each message, in order."""
        self._call(self._log, batch)

    def broadcast_time(self, ns: int) -> None:
        self._call(self._broadcast, wire.time_frame(ns))

    def status(self, client: int | None, level: int, message: str) -> None:
        """A status for ``client`` (None: every client)."""
        self._call(self._status, client, level, message)

    def clients(self) -> int:
        return len(self._clients)

    # --- the loop's side -----------------------------------------------------------------------
    def _add_channel(self, channel: ChannelInfo) -> None:
        self._channels[channel.id] = channel
        frame = wire.text("advertise", channels=[channel.advertisement()])
        for client in self._clients.values():
            self._control(client, frame)

    def _remove_channel(self, channel: int) -> None:
        if self._channels.pop(channel, None) is None:
            return
        frame = wire.text("unadvertise", channelIds=[channel])
        for client in self._clients.values():
            sub = client.by_channel.pop(channel, None)
            if sub is not None:
                del client.subscriptions[sub]
            self._control(client, frame)

    def _log(self, batch: list[tuple[int, int, bytes]]) -> None:
        clients = self._clients.values()
        for channel, stamp, payload in batch:
            for client in clients:
                sub = client.by_channel.get(channel)
                if sub is not None:
                    self._data(client, wire.message_data_header(sub, stamp) + payload)

    def _broadcast(self, frame: bytes) -> None:
        for client in self._clients.values():
            self._data(client, frame)

    def _status(self, client: int | None, level: int, message: str) -> None:
        frame = wire.text("status", level=level, message=message)
        targets = self._clients.values() if client is None else [self._clients.get(client)]
        for target in targets:
            if target is not None:
                self._control(target, frame)

    def _control(self, client: _Client, frame: str | bytes) -> None:
        if client.closing:
            return
        if len(client.control) >= CONTROL_BACKLOG:
            client.closing = True
            logger.warning(
                "foxglove: client %s reads too slowly (%d control messages waiting): disconnected",
                client.address,
                len(client.control),
            )
            # not a polite close: its frame would wait behind all that the client leaves unread
            client.ws.transport.abort()
            return
        client.control.append(frame)
        client.wake.set()

    def _data(self, client: _Client, frame: bytes) -> None:
        if len(client.data) == DATA_BACKLOG:
            client.dropped += 1
        client.data.append(frame)
        client.wake.set()

    async def _writer(self, client: _Client) -> None:
        """Sends what is queued for one client, control first."""
        while not client.closing:
            await client.wake.wait()
            client.wake.clear()
            while client.control or client.data:
                frame = client.control.popleft() if client.control else client.data.popleft()
                await client.ws.send(frame)

    async def _serve(self, ws: Any) -> None:
        from websockets.exceptions import ConnectionClosed

        host, port = (ws.remote_address or ("?", 0))[:2]
        client = _Client(next(self._ids), ws, f"{host}:{port}")
        self._clients[client.id] = client
        logger.info("foxglove: client %s connected", client.address)
        self._control(client, self._info)
        if self._channels:
            channels = [c.advertisement() for c in self._channels.values()]
            self._control(client, wire.text("advertise", channels=channels))
        writer = asyncio.create_task(self._writer(client))
        try:
            async for frame in ws:
                await self._receive(client, frame)
        except ConnectionClosed:
            pass
        finally:
            client.closing = True
            writer.cancel()
            del self._clients[client.id]
            self._forget(client)
            logger.info("foxglove: client %s left", client.address)
        with contextlib.suppress(asyncio.CancelledError, ConnectionClosed):
            await writer

    def _forget(self, client: _Client) -> None:
        """What a client that left had asked for, given back."""
        for channel in list(client.by_channel):
            self._tell(client, self.listener.on_unsubscribe, client.id, channel)
        for channel in list(client.client_channels):
            self._tell(client, self.listener.on_client_unadvertise, client.id, channel)

    def _tell(self, client: _Client, fn: Callable[..., None], *args: Any) -> None:
        """``fn(*args)`` of the listener; what it refuses goes back to ``client``."""
        try:
            fn(*args)
        except ProtocolError as err:
            self._status(client.id, StatusLevel.ERROR, str(err))
        except Exception:  # one client's request never stops the server
            logger.exception("foxglove: serving client %s", client.address)
            self._status(client.id, StatusLevel.ERROR, "internal error (see the bridge's log)")

    async def _receive(self, client: _Client, frame: str | bytes) -> None:
        try:
            request = wire.parse_text(frame) if isinstance(frame, str) else wire.parse_binary(frame)
        except ProtocolError as err:
            self._status(client.id, StatusLevel.ERROR, str(err))
            return
        if isinstance(request, wire.ClientMessage):
            if request.channel not in client.client_channels:
                text = f"unknown client channel id {request.channel}: advertise it first"
                self._status(client.id, StatusLevel.ERROR, text)
                return
            self._tell(
                client, self.listener.on_client_message, client.id, request.channel, request.data
            )
        elif isinstance(request, wire.Subscribe):
            self._subscribe(client, request)
        elif isinstance(request, wire.Unsubscribe):
            self._unsubscribe(client, request.ids)
        elif isinstance(request, wire.ClientAdvertise):
            self._client_advertise(client, request.channels)
        elif isinstance(request, wire.ClientUnadvertise):
            for channel in request.ids:
                if channel in client.client_channels:
                    client.client_channels.discard(channel)
                    self._tell(client, self.listener.on_client_unadvertise, client.id, channel)
        elif isinstance(request, wire.GetParameters | wire.SetParameters):
            await self._parameters_request(client, request)
        elif isinstance(request, wire.SubscribeParameterUpdates):
            if client.parameters is None or not request.names:
                client.parameters = set(request.names)
            elif client.parameters:
                client.parameters.update(request.names)
        elif isinstance(request, wire.UnsubscribeParameterUpdates):
            if not request.names or client.parameters is None:
                client.parameters = None
            else:
                client.parameters.difference_update(request.names)

    def _refuse(self, client: _Client, refusals: Sequence[str]) -> None:
        """One error status for what one request had refused (however many items)."""
        if refusals:
            text = "; ".join(refusals[:MAX_LISTED])
            if len(refusals) > MAX_LISTED:
                text += f"; and {len(refusals) - MAX_LISTED:,} more"
            self._status(client.id, StatusLevel.ERROR, text)

    def _subscribe(self, client: _Client, request: wire.Subscribe) -> None:
        refusals = []
        for sub, channel in request.subscriptions:
            if channel not in self._channels:
                refusals.append(f"Unknown channel ID: {channel}")
            elif sub in client.subscriptions:
                refusals.append(f"subscription id {sub} is in use; ignoring the subscription")
            elif channel in client.by_channel:
                refusals.append(f"channel {channel} is subscribed already; ignoring it")
            else:
                client.subscriptions[sub] = channel
                client.by_channel[channel] = sub
                self._tell(client, self.listener.on_subscribe, client.id, channel)
        self._refuse(client, refusals)

    def _unsubscribe(self, client: _Client, ids: Iterable[int]) -> None:
        unknown = []
        for sub in ids:
            channel = client.subscriptions.pop(sub, None)
            if channel is None:
                unknown.append(f"unknown subscription id {sub}: nothing to unsubscribe")
                continue
            del client.by_channel[channel]
            self._tell(client, self.listener.on_unsubscribe, client.id, channel)
        self._refuse(client, unknown)

    def _client_advertise(self, client: _Client, channels: Sequence[wire.ClientChannel]) -> None:
        refusals = []
        for channel in channels:
            if channel.id in client.client_channels:
                refusals.append(f"client channel id {channel.id} is advertised already")
            elif len(client.client_channels) >= MAX_CLIENT_CHANNELS:
                refusals.append(f"at most {MAX_CLIENT_CHANNELS} client channels at once")
            else:
                try:
                    self.listener.on_client_advertise(client.id, channel)
                except ProtocolError as err:
                    refusals.append(str(err))
                    continue
                client.client_channels.add(channel.id)
        self._refuse(client, refusals)

    async def _parameters_request(
        self, client: _Client, request: wire.GetParameters | wire.SetParameters
    ) -> None:
        try:
            refused: list[str] = []
            if isinstance(request, wire.GetParameters):
                values = await asyncio.to_thread(self.listener.get_parameters, request.names)
            else:
                values, refused = await asyncio.to_thread(
                    self.listener.set_parameters, request.parameters
                )
        except ProtocolError as err:
            self._status(client.id, StatusLevel.ERROR, str(err))
            return
        except Exception:  # one client's request never stops the server
            logger.exception("foxglove: parameters for client %s", client.address)
            self._status(client.id, StatusLevel.ERROR, "internal error (see the bridge's log)")
            return
        self._refuse(client, refused)
        if isinstance(request, wire.GetParameters) or request.id is not None:
            fields: dict[str, Any] = {"parameters": values}
            if request.id is not None:
                fields["id"] = request.id
            self._control(client, wire.text("parameterValues", **fields))

    async def _poll_parameters(self) -> None:
        """Tells clients following parameters what changed."""
        while True:
            await asyncio.sleep(PARAMETER_POLL_S)
            followers = [c for c in self._clients.values() if c.parameters is not None]
            if not followers:
                self._parameters.clear()
                continue
            try:
                values = await asyncio.to_thread(self.listener.get_parameters, ())
            except Exception:  # the next poll tries again
                logger.debug("foxglove: reading the parameters failed", exc_info=True)
                continue
            now = {str(p["name"]): p for p in values}
            changed = [p for n, p in now.items() if self._parameters.get(n) != p]
            self._parameters = now
            for client in followers:
                wanted = client.parameters
                told = [p for p in changed if not wanted or p["name"] in wanted]
                if told:
                    self._control(client, wire.text("parameterValues", parameters=told))
