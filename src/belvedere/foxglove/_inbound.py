"""What clients send the graph: messages they publish, parameters they read and set.

Called on the SDK's threads. Messages are decoded there and published on the executor
(publishers are made and removed there too, in the order the client asked).
"""

from __future__ import annotations

import json
import logging
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING, Any, Final

from belvedere.errors import BelvedereError
from belvedere.graph import Graph, GraphError, Node, Publisher, ZenohTransport
from belvedere.msgs import message_from_data, short, types

if TYPE_CHECKING:
    import foxglove

__all__ = ["ClientPublishing", "Parameters"]

logger = logging.getLogger("belvedere.foxglove")


@dataclass
class _ClientTopic:
    topic: str
    msgtype: str
    encoding: str
    publisher: Publisher | None = None


class ClientPublishing:
    """Clients' channels (Foxglove's Publish panel) as publishers of the bridge's node."""

    ENCODINGS: Final = ("ros1", "json")

    def __init__(self, node: Node) -> None:
        self.node = node
        self.status: Callable[..., None] | None = None
        """The server's ``publish_status`` (set once it runs)."""
        self._topics: dict[tuple[int, int], _ClientTopic] = {}

    def advertise(self, client: int, channel: int, topic: str, encoding: str, schema: str) -> None:
        if encoding not in self.ENCODINGS:
            self._refuse(f"cannot publish on {topic} in {encoding!r}: use ros1 or json")
            return
        try:
            msgtype = types().resolve(schema)
        except BelvedereError as err:
            self._refuse(f"cannot publish on {topic}: {err.message}")
            return
        entry = _ClientTopic(topic, msgtype, encoding)
        self._topics[client, channel] = entry
        self.node.graph.executor.post(partial(self._open, entry))

    def unadvertise(self, client: int, channel: int) -> None:
        entry = self._topics.pop((client, channel), None)
        if entry is not None:
            self.node.graph.executor.post(partial(self._close, entry))

    def message(self, client: int, channel: int, data: bytes) -> None:
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
            self._refuse(f"a message for {entry.topic} is not a {short(entry.msgtype)}: {what}")
            return
        self.node.graph.executor.post(partial(self._publish, entry, msg))

    # --- executor thread ------------------------------------------------------------------------
    def _open(self, entry: _ClientTopic) -> None:
        try:
            entry.publisher = self.node.publisher(entry.topic, entry.msgtype, queue_size=10)
        except GraphError as err:
            self._refuse(err.message)

    def _close(self, entry: _ClientTopic) -> None:
        if entry.publisher is not None:
            entry.publisher.unregister()
            entry.publisher = None

    def _publish(self, entry: _ClientTopic, msg: Any) -> None:
        if entry.publisher is not None:
            entry.publisher.publish(msg)

    def _refuse(self, text: str) -> None:
        logger.warning("foxglove: %s", text)
        if self.status is not None:
            from foxglove import StatusLevel

            self.status(text, StatusLevel.Error)


class Parameters:
    """The graph's parameters as Foxglove's: each leaf by its full name (``/a/b``).

    A graph of this process holds its own; a bridge joined to a running graph asks the
    graph that holds them, as every tool does."""

    def __init__(self, graph: Graph) -> None:
        self.graph = graph
        transport = graph.transport
        self._remote = isinstance(transport, ZenohTransport) and not transport.serve_params

    def _all(self) -> dict[str, Any]:
        if self._remote:
            transport = self.graph.transport
            assert isinstance(transport, ZenohTransport)
            try:
                tree = transport.param_request({"op": "get", "name": "/"})
            except GraphError as err:
                logger.warning("foxglove: cannot read the parameters: %s", err.message)
                return {}
        else:
            tree = self.graph.params.get("/")
        leaves: dict[str, Any] = {}
        _flatten(tree, "", leaves)
        return leaves

    def _set(self, name: str, value: Any) -> None:
        transport = self.graph.transport
        if self._remote:
            assert isinstance(transport, ZenohTransport)
            transport.param_request({"op": "set", "name": name, "value": value})
        else:
            self.graph.params.set(name, value)

    def get(self, names: list[str]) -> list[foxglove.Parameter]:
        values = self._all()
        wanted = names or sorted(values)
        return [p for n in wanted if n in values for p in _parameter(n, values[n])]

    def set(self, parameters: list[foxglove.Parameter]) -> list[foxglove.Parameter]:
        for param in parameters:
            try:
                self._set(param.name, param.get_value())
            except BelvedereError as err:
                logger.warning("foxglove: cannot set %s: %s", param.name, err.message)
        return self.get([p.name for p in parameters])


def _flatten(tree: Any, prefix: str, into: dict[str, Any]) -> None:
    if isinstance(tree, dict) and tree:
        for key, value in tree.items():
            _flatten(value, f"{prefix}/{key}", into)
    elif prefix:
        into[prefix] = tree


def _parameter(name: str, value: Any) -> list[foxglove.Parameter]:
    """The parameter (none for a value Foxglove cannot carry: a list of mixed kinds)."""
    from foxglove import Parameter, ParameterType

    kind = None
    if isinstance(value, float):
        kind = ParameterType.Float64
    elif isinstance(value, list) and value and all(isinstance(v, float) for v in value):
        kind = ParameterType.Float64Array
    try:
        return [Parameter(name, value=value, type=kind)]
    except (TypeError, ValueError) as err:
        logger.debug("foxglove: parameter %s not served: %s", name, err)
        return []
