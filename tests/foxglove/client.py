"""A Foxglove WebSocket client, as the Foxglove app speaks the protocol (``foxglove.sdk.v1``,
formerly ``foxglove.websocket.v1``): JSON text frames for control, binary frames for data.

Only what the tests and the benchmark use: the server's info, channels advertised and
withdrawn, subscriptions and their messages, the server's time, client channels and their
messages, parameters and status messages.
"""

from __future__ import annotations

import json
import struct
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final, TypeVar

from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect
from websockets.typing import Subprotocol

from tests.waiting import DEADLINE

__all__ = ["SUBPROTOCOLS", "FoxgloveClient", "Message"]

SUBPROTOCOLS: Final = (Subprotocol("foxglove.sdk.v1"), Subprotocol("foxglove.websocket.v1"))
"""What the Foxglove app offers, newest first."""

_MESSAGE_DATA: Final = 0x01
_TIME: Final = 0x02
_HEAD: Final = struct.Struct("<BIQ")
_TIME_FRAME: Final = struct.Struct("<BQ")
_CLIENT_DATA: Final = struct.Struct("<BI")

T = TypeVar("T")


@dataclass(frozen=True)
class Message:
    """One messageData frame."""

    subscription: int
    log_time: int
    data: bytes


class FoxgloveClient:
    """One connection; :meth:`pump` reads frames into the lists below."""

    def __init__(self, url: str, *, origin: str | None = None) -> None:
        """``origin``: the ``Origin`` a web page would send (None: not a web page)."""
        self.ws: ClientConnection = connect(
            url,
            subprotocols=list(SUBPROTOCOLS),
            origin=origin,  # type: ignore[arg-type]
            proxy=None,
            open_timeout=DEADLINE,
            max_size=None,
            max_queue=None,
        )
        self.server_info: dict[str, Any] = {}
        self.channels: dict[int, dict[str, Any]] = {}
        """Advertised now, by id."""
        self.withdrawn: list[int] = []
        self.messages: list[Message] = []
        self.times: list[int] = []
        self.statuses: list[dict[str, Any]] = []
        self.parameters: dict[str, list[dict[str, Any]]] = {}
        """parameterValues replies, by request id."""
        self._next_id = 1
        self.wait(lambda: self.server_info, what="the server's info")

    @property
    def subprotocol(self) -> str | None:
        return self.ws.subprotocol

    def close(self) -> None:
        self.ws.close()

    # --- reading -------------------------------------------------------------------------
    def pump(self, timeout: float = 0.1) -> bool:
        """Read one frame (False if none came within ``timeout``)."""
        try:
            frame = self.ws.recv(timeout=timeout)
        except TimeoutError:
            return False
        if isinstance(frame, bytes):
            self._binary(frame)
        else:
            self._text(json.loads(frame))
        return True

    def _binary(self, frame: bytes) -> None:
        if frame[0] == _MESSAGE_DATA:
            _, sub, stamp = _HEAD.unpack_from(frame)
            self.messages.append(Message(sub, stamp, frame[_HEAD.size :]))
        elif frame[0] == _TIME:
            self.times.append(_TIME_FRAME.unpack_from(frame)[1])

    def _text(self, doc: dict[str, Any]) -> None:
        op = doc["op"]
        if op == "serverInfo":
            self.server_info = doc
        elif op == "advertise":
            for channel in doc["channels"]:
                self.channels[channel["id"]] = channel
        elif op == "unadvertise":
            for cid in doc["channelIds"]:
                self.channels.pop(cid, None)
                self.withdrawn.append(cid)
        elif op == "status":
            self.statuses.append(doc)
        elif op == "parameterValues":
            self.parameters[doc.get("id", "")] = doc["parameters"]

    def wait(self, predicate: Callable[[], T | None], *, what: str, timeout: float = DEADLINE) -> T:
        """Read frames until ``predicate()`` is truthy (its value)."""
        deadline = time.monotonic() + timeout
        while True:
            value = predicate()
            if value:
                return value
            if time.monotonic() >= deadline:
                msg = f"timed out waiting for {what}"
                raise AssertionError(msg)
            try:
                self.pump()
            except ConnectionClosed as err:
                msg = f"the server closed the connection while waiting for {what}: {err}"
                raise AssertionError(msg) from err

    def channel(self, topic: str) -> dict[str, Any]:
        """The advertised channel of ``topic``, waiting for it."""

        def find() -> dict[str, Any] | None:
            return next((c for c in self.channels.values() if c["topic"] == topic), None)

        found: dict[str, Any] = self.wait(find, what=f"a channel for {topic}")
        return found

    # --- asking ------------------------------------------------------------------------------
    def _send(self, doc: dict[str, Any]) -> None:
        self.ws.send(json.dumps(doc))

    def _id(self) -> int:
        value = self._next_id
        self._next_id += 1
        return value

    def subscribe(self, topic: str) -> int:
        """Subscribe to ``topic``'s channel; the subscription's id."""
        sub = self._id()
        channel = self.channel(topic)["id"]
        self._send_subscribe(sub, channel)
        return sub

    def _send_subscribe(self, sub: int, channel: int) -> None:
        self._send({"op": "subscribe", "subscriptions": [{"id": sub, "channelId": channel}]})

    def unsubscribe(self, sub: int) -> None:
        self._send({"op": "unsubscribe", "subscriptionIds": [sub]})

    def received(self, sub: int) -> list[Message]:
        return [m for m in self.messages if m.subscription == sub]

    def advertise(self, topic: str, encoding: str, schema_name: str) -> int:
        """A client channel (the Publish panel's); its id."""
        cid = self._id()
        channel = {"id": cid, "topic": topic, "encoding": encoding, "schemaName": schema_name}
        self._send({"op": "advertise", "channels": [channel]})
        return cid

    def unadvertise(self, cid: int) -> None:
        self._send({"op": "unadvertise", "channelIds": [cid]})

    def publish(self, cid: int, data: bytes) -> None:
        self.ws.send(_CLIENT_DATA.pack(_MESSAGE_DATA, cid) + data)

    def get_parameters(self, names: list[str]) -> list[dict[str, Any]]:
        request = f"get-{self._id()}"
        self._send({"op": "getParameters", "parameterNames": names, "id": request})
        found: list[dict[str, Any]] = self.wait(
            lambda: self.parameters.get(request), what="the parameters"
        )
        return found

    def set_parameters(self, values: dict[str, Any]) -> list[dict[str, Any]]:
        request = f"set-{self._id()}"
        params = [{"name": n, "value": v} for n, v in values.items()]
        self._send({"op": "setParameters", "parameters": params, "id": request})
        found: list[dict[str, Any]] = self.wait(
            lambda: self.parameters.get(request), what="the parameters set"
        )
        return found
