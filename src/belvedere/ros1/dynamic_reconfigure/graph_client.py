"""dynamic_reconfigure's client for belvedere's own tools (rqt_reconfigure's page): the
servers on the graph, found as rqt_reconfigure finds them, and one server's description,
configuration and ``set_parameters`` on a graph node — the counterpart of
:mod:`.graph_server`, without rospy.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from typing import Any, Final, TypeVar

from belvedere.graph import Graph, GraphTopics, Node, ZenohTransport
from belvedere.msgs import message_to_data, short
from belvedere.ros1.dynamic_reconfigure._description import (
    Description,
    config_data,
    config_values,
)
from belvedere.ros1.dynamic_reconfigure._encoding import decode_description

__all__ = ["DESCRIPTIONS", "SERVICE", "GraphClient", "find_servers"]

SERVICE: Final = "/set_parameters"
DESCRIPTIONS: Final = "/parameter_descriptions"
_RECONFIGURE: Final = "dynamic_reconfigure/Reconfigure"
_DESCRIPTION_TYPE: Final = "dynamic_reconfigure/ConfigDescription"
_STRUCTURE_TIMEOUT: Final = 10.0
"""Seconds the executor may take to get to a subscription (it runs one callback at a time)."""
T = TypeVar("T")


def find_servers(node: Node, topics: GraphTopics, *, timeout: float = 1.0) -> list[str]:
    """Every dynamic_reconfigure server on ``node``'s graph, sorted: the namespaces of the
    services ``*/set_parameters`` of type ``Reconfigure`` (here and in other processes) and
    of the topics ``*/parameter_descriptions`` (as rqt_reconfigure looks for both).
    ``timeout``: how long other processes may take to answer."""
    graph = node.graph
    found = {
        name.removesuffix(SERVICE)
        for name, server in list(graph.services.items())
        if name.endswith(SERVICE) and short(server.type) == _RECONFIGURE
    }
    if isinstance(graph.transport, ZenohTransport):
        for name, offers in graph.transport.info(timeout=timeout).services.items():
            if name.endswith(SERVICE) and any(short(t) == _RECONFIGURE for t, _ in offers):
                found.add(name.removesuffix(SERVICE))
    found.update(t.removesuffix(DESCRIPTIONS) for t in topics.of_type(_DESCRIPTION_TYPE))
    return sorted(n for n in found if n)


class GraphClient:
    """Server ``name``'s parameters as ``node`` sees them: :attr:`description` and
    :attr:`config` follow its latched topics (``on_change`` is called after each, on the
    graph's executor), :meth:`set` changes them through ``set_parameters``."""

    def __init__(
        self, node: Node, name: str, on_change: Callable[[GraphClient], object] | None = None
    ) -> None:
        self.node = node
        self.name = name
        self.description: Description | None = None
        self.config: dict[str, Any] = {}
        self.on_change = on_change
        self._lock = threading.Lock()
        self._subs = _on_executor(
            node.graph,
            lambda: [
                node.subscribe(name + DESCRIPTIONS, _DESCRIPTION_TYPE, self._described),
                node.subscribe(
                    name + "/parameter_updates", "dynamic_reconfigure/Config", self._updated
                ),
            ],
        )

    def _described(self, msg: Any) -> None:
        with self._lock:
            self.description = decode_description(message_to_data(msg))
        self._changed()

    def _updated(self, msg: Any) -> None:
        with self._lock:
            self.config = config_values(message_to_data(msg))
        self._changed()

    def _changed(self) -> None:
        if self.on_change is not None:
            self.on_change(self)

    def set(self, changes: Mapping[str, Any], *, timeout: float = 5.0) -> dict[str, Any]:
        """Ask the server for ``changes``; the configuration it answers with (its values
        clamped, its callback's corrections). Call from any thread but the executor's.

        Raises:
            ServiceFailedError: the server refused them (an unknown name, a value outside
                an enum, its callback's refusal).
            ServiceUnavailableError: no server answers.
        """
        service = self.name + SERVICE
        request = {"config": config_data(dict(changes), [])}
        graph = self.node.graph

        def call() -> Any:
            return self.node.call_service(service, _RECONFIGURE, request, timeout=timeout)

        # A server of this process runs its callback on the executor, as every callback of
        # a graph does; another process's answers over the transport, waited for here.
        reply = graph.executor.call(call, timeout) if service in graph.services else call()
        answered = config_values(message_to_data(reply.config))
        with self._lock:
            self.config = answered
        return answered

    def close(self) -> None:
        def unregister() -> None:
            for sub in self._subs:
                sub.unregister()

        _on_executor(self.node.graph, unregister)


def _on_executor(graph: Graph, fn: Callable[[], T]) -> T:
    """``fn()`` where a graph's structure may change: on its executor's thread (waited for
    from any other), or here when the executor does not run."""
    if graph.on_executor_thread() or graph.executor.stopped:
        return fn()
    return graph.executor.call(fn, _STRUCTURE_TIMEOUT)
