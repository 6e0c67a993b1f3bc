"""What clients send the graph: messages they publish, parameters they read and set.

Everything here is a client's input: a topic or parameter name is checked as a graph name, a
type must be known, a message must decode as its channel's type — each refusal is a
:class:`ProtocolError` (an error status to that client), before anything reaches the graph.
Messages are decoded on the server's thread and published on the executor (publishers are
made and removed there too, in the order the client asked); parameters are read and set on a
worker thread (another process's graph may hold them).
"""

from __future__ import annotations

import json
import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any, Final

from belvedere.errors import BelvedereError
from belvedere.foxglove._protocol import ClientChannel, ProtocolError
from belvedere.graph import Graph, Node, Publisher, ZenohTransport, validate_name
from belvedere.msgs import message_from_data, short, types

__all__ = ["ClientPublishing", "Parameters"]

logger = logging.getLogger("belvedere.foxglove")

Status = Callable[[int | None, int, str], None]
"""The server's ``status(client, level, text)``."""
ERROR: Final = 2


@dataclass
class _ClientTopic:
    client: int
    topic: str
    msgtype: str
    encoding: str
    publisher: Publisher | None = None


class ClientPublishing:
    """Clients' channels (Foxglove's Publish panel) as publishers of the bridge's node."""

    ENCODINGS: Final = ("ros1", "json")

    def __init__(self, node: Node) -> None:
        self.node = node
        self.status: Status | None = None
        """The server's ``status`` (set once it runs): how the executor's refusals reach the
        client."""
        self._topics: dict[tuple[int, int], _ClientTopic] = {}

    def advertise(self, client: int, channel: ClientChannel) -> None:
        """Raises ProtocolError: a bad name, encoding or type."""
        try:
            topic = validate_name(self.node.resolve(channel.topic))
        except BelvedereError as err:
            msg = f"cannot publish on {channel.topic!r}: {err.message}"
            raise ProtocolError(msg) from None
        if channel.encoding not in self.ENCODINGS:
            msg = f"cannot publish on {topic} in {channel.encoding[:64]!r}: use ros1 or json"
            raise ProtocolError(msg)
        try:
            msgtype = types().resolve(channel.schema_name)
        except BelvedereError as err:
            msg = f"cannot publish on {topic}: {err.message}"
            raise ProtocolError(msg) from None
        entry = _ClientTopic(client, topic, msgtype, channel.encoding)
        self._topics[client, channel.id] = entry
        self.node.graph.executor.post(partial(self._open, entry))

    def unadvertise(self, client: int, channel: int) -> None:
        entry = self._topics.pop((client, channel), None)
        if entry is not None:
            self.node.graph.executor.post(partial(self._close, entry))

    def message(self, client: int, channel: int, data: bytes) -> None:
        """Raises ProtocolError: the data is not a message of the channel's type."""
        entry = self._topics.get((client, channel))
        if entry is None:
            return
        try:
            if entry.encoding == "json":
                msg = message_from_data(entry.msgtype, json.loads(data))
            else:
                msg = types().store.deserialize_ros1(data, entry.msgtype)
        except Exception as err:  # noqa: BLE001 (a client sent something else)
            what = err.message if isinstance(err, BelvedereError) else str(err) or repr(err)
            text = f"a message for {entry.topic} is not a {short(entry.msgtype)}: {what[:200]}"
            raise ProtocolError(text) from None
        self.node.graph.executor.post(partial(self._publish, entry, msg))

    # --- executor thread ------------------------------------------------------------------------
    def _open(self, entry: _ClientTopic) -> None:
        try:
            entry.publisher = self.node.publisher(entry.topic, entry.msgtype, queue_size=10)
        except BelvedereError as err:
            self._refuse(entry.client, err.message)

    def _close(self, entry: _ClientTopic) -> None:
        if entry.publisher is not None:
            entry.publisher.unregister()
            entry.publisher = None

    def _publish(self, entry: _ClientTopic, msg: Any) -> None:
        if entry.publisher is None:
            return
        try:
            entry.publisher.publish(msg)
        except BelvedereError as err:
            self._refuse(entry.client, f"cannot publish on {entry.topic}: {err.message}")

    def _refuse(self, client: int, text: str) -> None:
        logger.warning("foxglove: %s", text)
        if self.status is not None:
            self.status(client, ERROR, text)


class Parameters:
    """The graph's parameters as Foxglove's: each leaf by its full name (``/a/b``).

    A graph of this process holds its own; a bridge joined to a running graph asks the
    graph that holds them, as every tool does."""

    def __init__(self, graph: Graph) -> None:
        self.graph = graph
        transport = graph.transport
        self._remote = isinstance(transport, ZenohTransport) and not transport.serve_params

    def _request(self, request: dict[str, Any]) -> Any:
        transport = self.graph.transport
        assert isinstance(transport, ZenohTransport)
        return transport.param_request(request)

    def _all(self) -> dict[str, Any]:
        try:
            tree = self._request({"op": "get", "name": "/"}) if self._remote else None
        except BelvedereError as err:
            logger.warning("foxglove: cannot read the parameters: %s", err.message)
            return {}
        if not self._remote:
            tree = self.graph.params.get("/")
        leaves: dict[str, Any] = {}
        _flatten(tree, "", leaves)
        return leaves

    def _set(self, name: str, value: Any) -> None:
        if value is None:
            if self._remote:
                self._request({"op": "delete", "name": name})
            else:
                self.graph.params.delete(name)
        elif self._remote:
            self._request({"op": "set", "name": name, "value": value})
        else:
            self.graph.params.set(name, value)

    def get(self, names: Sequence[str]) -> list[dict[str, Any]]:
        values = self._all()
        wanted = names or sorted(values)
        return [p for n in wanted if n in values for p in _parameter(n, values[n])]

    def set(self, parameters: Sequence[tuple[str, Any]]) -> tuple[list[dict[str, Any]], list[str]]:
        """Set each (a value of None unsets it); the values now, and what was refused."""
        refused = []
        for name, value in parameters:
            try:
                if name == "/":
                    msg = "the whole parameter tree cannot be set from Foxglove"
                    raise ProtocolError(msg)
                self._set(validate_name(name), value)
            except (BelvedereError, ProtocolError) as err:
                text = err.message if isinstance(err, BelvedereError) else str(err)
                refused.append(f"cannot set {name[:200]!r}: {text}")
        return self.get([n for n, _ in parameters]), refused


def _flatten(tree: Any, prefix: str, into: dict[str, Any]) -> None:
    if isinstance(tree, dict) and tree:
        for key, value in tree.items():
            _flatten(value, f"{prefix}/{key}", into)
    elif prefix:
        into[prefix] = tree


def _jsonable(value: Any) -> bool:
    """Can Foxglove's JSON carry it (no NaN, no infinity, no bytes)?"""
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, bool | int | str):
        return True
    if isinstance(value, list):
        return all(_jsonable(v) for v in value)
    if isinstance(value, dict):
        return all(isinstance(k, str) and _jsonable(v) for k, v in value.items())
    return False


def _parameter(name: str, value: Any) -> list[dict[str, Any]]:
    """The parameter as Foxglove reads it (none for a value JSON cannot carry)."""
    if not _jsonable(value):
        logger.debug("foxglove: parameter %s not served: %r", name, value)
        return []
    if isinstance(value, float):
        return [{"name": name, "type": "float64", "value": value}]
    if isinstance(value, list) and value and all(isinstance(v, float) for v in value):
        return [{"name": name, "type": "float64_array", "value": value}]
    return [{"name": name, "value": value}]
