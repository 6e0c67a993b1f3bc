"""ROS 1's master, over XML-RPC: the Master API (who publishes, subscribes and serves what)
and the Parameter Server API, with rosmaster's codes and texts.

ROS 1 programs register here as with roscore. The graph's own nodes, topics and services
(``Peers``) are merged into every answer, so ``rostopic list`` shows belvedere's topics and
a ROS 1 subscriber is given the bridge as a publisher of a topic belvedere publishes."""

from __future__ import annotations

import logging
import os
import re
import threading
import xmlrpc.client
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any, Protocol

from belvedere.errors import BelvedereError
from belvedere.ros1wire._params import GraphParams, resolve_key
from belvedere.ros1wire._xmlrpc import XmlRpcServer, server_proxy

__all__ = ["Master", "MasterSide", "Peers", "Registrations"]

logger = logging.getLogger("belvedere.ros1wire")

Reply = list[Any]
SUCCESS, FAILURE, ERROR = 1, 0, -1


class Peers(Protocol):
    """The graph's side, as the master shows it to ROS 1 programs."""

    uri: str
    """The slave API every graph node answers at (the bridge's)."""

    def graph_state(self) -> Registrations: ...

    def service_uri(self) -> str: ...

    def ros1_changed(self, topic: str) -> None:
        """A ROS 1 program registered or unregistered on ``topic``."""


class MasterSide(Protocol):
    """What the bridge needs of a master: this process's own (:class:`Master`) or a running
    one it registers with (``ros1wire._remote``)."""

    uri: str

    def attach(self, peers: Peers) -> None: ...

    def ros1_view(self) -> Registrations:
        """The ROS 1 programs' registrations (a copy): topic → {node: type}, node → API."""
        ...

    def graph_changed(self, before: Registrations, after: Registrations) -> None:
        """The graph's publishers, subscribers or services changed."""

    def publishers_updated(self, topic: str, uris: list[str]) -> None:
        """The master said who publishes ``topic`` now (``publisherUpdate``)."""


@dataclass
class Registrations:
    """topic → {node: type} of publishers and subscribers; service → {node: URI}; node →
    its slave API's URI."""

    publishers: dict[str, dict[str, str]] = field(default_factory=dict)
    subscribers: dict[str, dict[str, str]] = field(default_factory=dict)
    services: dict[str, dict[str, str]] = field(default_factory=dict)
    nodes: dict[str, str] = field(default_factory=dict)

    def copy(self) -> Registrations:
        return Registrations(
            {k: dict(v) for k, v in self.publishers.items()},
            {k: dict(v) for k, v in self.subscribers.items()},
            {k: dict(v) for k, v in self.services.items()},
            dict(self.nodes),
        )

    def topic_type(self, topic: str) -> str | None:
        for table in (self.publishers, self.subscribers):
            for typ in table.get(topic, {}).values():
                if typ != "*":
                    return typ
        return None


class Master:
    """Serve on ``host``:``port`` (0: a free port) with the graph's parameters; ``peers``
    once the bridge exists (:meth:`attach`)."""

    def __init__(self, params: GraphParams, host: str = "127.0.0.1", port: int = 11311) -> None:
        self.params = params
        self.ros1 = Registrations()
        self.peers: Peers | None = None
        self._lock = threading.RLock()
        self._param_subscribers: dict[str, set[tuple[str, str]]] = {}
        """resolved key → {(caller_id, caller_api)}"""
        self._calls = ThreadPoolExecutor(max_workers=4, thread_name_prefix="belvedere-master")
        self.server = XmlRpcServer(host, port, self._dispatch)
        self.uri = self.server.uri

    def attach(self, peers: Peers) -> None:
        self.peers = peers

    def close(self) -> None:
        self.server.close()
        self._calls.shutdown(wait=False, cancel_futures=True)

    def ros1_view(self) -> Registrations:
        with self._lock:
            return self.ros1.copy()

    def graph_changed(self, before: Registrations, after: Registrations) -> None:
        for topic in set(before.publishers) ^ set(after.publishers):
            self.publisher_update(topic)

    def publishers_updated(self, topic: str, uris: list[str]) -> None:
        pass  # this master sends publisherUpdate; it is never sent one

    # --- calls out ------------------------------------------------------------------------------
    def _call_later(self, uri: str, method: str, *args: Any) -> None:
        """Tell a node something (publisherUpdate, paramUpdate, shutdown) without waiting:
        a node that does not answer must not hold up the master."""

        def call() -> None:
            try:
                getattr(server_proxy(uri, timeout=5.0), method)(*args)
            except (OSError, xmlrpc.client.Error) as err:
                logger.debug("master: %s at %s failed: %s", method, uri, err)

        self._calls.submit(call)

    def publisher_update(self, topic: str) -> None:
        """Tell the ROS 1 subscribers of ``topic`` who publishes it now."""
        uris = self._publisher_uris(topic)
        with self._lock:
            apis = self._apis(self.ros1.subscribers.get(topic, {}))
        for api in apis:
            self._call_later(api, "publisherUpdate", "/master", topic, uris)

    def _apis(self, nodes: dict[str, str]) -> list[str]:
        """The slave APIs of ROS 1 ``nodes`` (under the lock)."""
        return [self.ros1.nodes[n] for n in nodes if n in self.ros1.nodes]

    # --- the merged view -------------------------------------------------------------------------
    def _graph(self) -> Registrations:
        return self.peers.graph_state() if self.peers is not None else Registrations()

    def _publisher_uris(self, topic: str) -> list[str]:
        with self._lock:
            uris = [
                self.ros1.nodes[n]
                for n in self.ros1.publishers.get(topic, {})
                if n in self.ros1.nodes
            ]
        if self.peers is not None and self._graph().publishers.get(topic):
            uris.append(self.peers.uri)
        return uris

    def _merged(self) -> Registrations:
        graph = self._graph()
        with self._lock:
            out = Registrations()
            for name in ("publishers", "subscribers", "services"):
                merged: dict[str, dict[str, str]] = {}
                for table in (getattr(graph, name), getattr(self.ros1, name)):
                    for key, users in table.items():
                        merged.setdefault(key, {}).update(users)
                setattr(out, name, merged)
            out.nodes = {**graph.nodes, **self.ros1.nodes}
        return out

    # --- dispatch ---------------------------------------------------------------------------------
    def _dispatch(self, method: str, params: tuple[Any, ...]) -> Any:
        handler: Callable[..., Reply] | None = getattr(self, f"api_{_snake(method)}", None)
        if handler is None:
            msg = f'method "{method}" is not supported'
            raise xmlrpc.client.Fault(1, msg)
        try:
            return handler(*params)
        except TypeError as err:
            return [ERROR, f"bad arguments to {method}: {err}", 0]
        except BelvedereError as err:
            return [ERROR, err.message, 0]

    def _node(self, caller_id: str, caller_api: str) -> None:
        """Register a node's API; a node that took a name in use is the one that stays, and
        the one before is told to shut down, as rosmaster does."""
        with self._lock:
            before = self.ros1.nodes.get(caller_id)
            self.ros1.nodes[caller_id] = caller_api
        if before is not None and before != caller_api:
            self._call_later(before, "shutdown", "/master", "new node registered with same name")

    # --- the Master API ------------------------------------------------------------------------
    def api_get_uri(self, caller_id: str) -> Reply:
        return [SUCCESS, "", self.uri]

    def api_get_pid(self, caller_id: str) -> Reply:
        return [SUCCESS, "", os.getpid()]

    def api_register_service(
        self, caller_id: str, service: str, service_api: str, caller_api: str
    ) -> Reply:
        self._node(caller_id, caller_api)
        with self._lock:
            self.ros1.services.setdefault(service, {}).clear()
            self.ros1.services[service][caller_id] = service_api
        return [SUCCESS, f"Registered [{caller_id}] as provider of [{service}]", 1]

    def api_unregister_service(self, caller_id: str, service: str, service_api: str) -> Reply:
        with self._lock:
            providers = self.ros1.services.get(service, {})
            if providers.get(caller_id) != service_api:
                return [SUCCESS, f"[{caller_id}] is not a provider of [{service}]", 0]
            del providers[caller_id]
            if not providers:
                del self.ros1.services[service]
        return [SUCCESS, f"Unregistered [{caller_id}] as provider of [{service}]", 1]

    def api_lookup_service(self, caller_id: str, service: str) -> Reply:
        with self._lock:
            providers = list(self.ros1.services.get(service, {}).values())
        if providers:
            return [SUCCESS, f"rosrpc URI: [{providers[0]}]", providers[0]]
        if self.peers is not None and self._graph().services.get(service):
            uri = self.peers.service_uri()
            return [SUCCESS, f"rosrpc URI: [{uri}]", uri]
        return [ERROR, "no provider", ""]

    def api_register_subscriber(
        self, caller_id: str, topic: str, topic_type: str, caller_api: str
    ) -> Reply:
        self._node(caller_id, caller_api)
        with self._lock:
            self.ros1.subscribers.setdefault(topic, {})[caller_id] = topic_type
        if self.peers is not None:
            self.peers.ros1_changed(topic)
        return [SUCCESS, f"Subscribed to [{topic}]", self._publisher_uris(topic)]

    def api_unregister_subscriber(self, caller_id: str, topic: str, caller_api: str) -> Reply:
        with self._lock:
            users = self.ros1.subscribers.get(topic, {})
            if caller_id not in users:
                return [SUCCESS, f"[{caller_id}] is not a subscriber of [{topic}]", 0]
            del users[caller_id]
            if not users:
                del self.ros1.subscribers[topic]
        if self.peers is not None:
            self.peers.ros1_changed(topic)
        return [SUCCESS, f"Unregistered [{caller_id}] as subscriber of [{topic}]", 1]

    def api_register_publisher(
        self, caller_id: str, topic: str, topic_type: str, caller_api: str
    ) -> Reply:
        self._node(caller_id, caller_api)
        with self._lock:
            self.ros1.publishers.setdefault(topic, {})[caller_id] = topic_type
            subscribers = [
                self.ros1.nodes[n]
                for n in self.ros1.subscribers.get(topic, {})
                if n in self.ros1.nodes
            ]
        self.publisher_update(topic)
        if self.peers is not None:
            self.peers.ros1_changed(topic)
        return [SUCCESS, f"Registered [{caller_id}] as publisher of [{topic}]", subscribers]

    def api_unregister_publisher(self, caller_id: str, topic: str, caller_api: str) -> Reply:
        with self._lock:
            users = self.ros1.publishers.get(topic, {})
            if caller_id not in users:
                return [SUCCESS, f"[{caller_id}] is not a publisher of [{topic}]", 0]
            del users[caller_id]
            if not users:
                del self.ros1.publishers[topic]
        self.publisher_update(topic)
        if self.peers is not None:
            self.peers.ros1_changed(topic)
        return [SUCCESS, f"Unregistered [{caller_id}] as publisher of [{topic}]", 1]

    def api_lookup_node(self, caller_id: str, node_name: str) -> Reply:
        uri = self._merged().nodes.get(node_name)
        if uri is None:
            return [ERROR, f"unknown node [{node_name}]", ""]
        return [SUCCESS, "node api", uri]

    def api_get_published_topics(self, caller_id: str, subgraph: str) -> Reply:
        merged = self._merged()
        prefix = subgraph.rstrip("/") + "/" if subgraph.strip("/") else "/"
        topics = [
            [topic, merged.topic_type(topic) or "*"]
            for topic in sorted(merged.publishers)
            if merged.publishers[topic] and topic.startswith(prefix)
        ]
        return [SUCCESS, "current topics", topics]

    def api_get_topic_types(self, caller_id: str) -> Reply:
        merged = self._merged()
        names = sorted(set(merged.publishers) | set(merged.subscribers))
        return [SUCCESS, "current system state", [[t, merged.topic_type(t) or "*"] for t in names]]

    def api_get_system_state(self, caller_id: str) -> Reply:
        merged = self._merged()

        def listing(table: dict[str, dict[str, str]]) -> list[list[Any]]:
            return [[name, sorted(users)] for name, users in sorted(table.items()) if users]

        state = [listing(merged.publishers), listing(merged.subscribers), listing(merged.services)]
        return [SUCCESS, "current system state", state]

    # --- the Parameter Server API --------------------------------------------------------------
    def api_get_param(self, caller_id: str, key: str) -> Reply:
        name = resolve_key(key, caller_id)
        if not self.params.has(name):
            return [ERROR, f"Parameter [{name}] is not set", 0]
        return [SUCCESS, f"Parameter [{name}]", _xmlrpc_value(self.params.get(name))]

    def api_set_param(self, caller_id: str, key: str, value: Any) -> Reply:
        name = resolve_key(key, caller_id)
        if name == "/" and not isinstance(value, dict):
            return [ERROR, "cannot set root of parameter tree to non-dictionary", 0]
        self.params.set(name, value)
        self._param_changed(name)
        return [SUCCESS, f"parameter {name} set", 0]

    def api_delete_param(self, caller_id: str, key: str) -> Reply:
        name = resolve_key(key, caller_id)
        if not self.params.has(name):
            return [ERROR, f"parameter [{name}] is not set", 0]
        self.params.delete(name)
        self._param_changed(name)
        return [SUCCESS, f"parameter {name} deleted", 0]

    def api_has_param(self, caller_id: str, key: str) -> Reply:
        name = resolve_key(key, caller_id)
        return [SUCCESS, name, self.params.has(name)]

    def api_get_param_names(self, caller_id: str) -> Reply:
        return [SUCCESS, "Parameter names", self.params.names()]

    def api_search_param(self, caller_id: str, key: str) -> Reply:
        """The nearest ``key`` up from the caller's namespace (its first part is searched
        for; the rest is joined on)."""
        if key.startswith("/"):
            found = key if self.params.has(key) else None
        else:
            first, _, rest = key.lstrip("~").partition("/")
            namespace = caller_id.rsplit("/", 1)[0] if key[0] != "~" else caller_id
            found = None
            while True:
                candidate = f"{namespace}/{first}"
                if self.params.has(candidate):
                    found = f"{candidate}/{rest}" if rest else candidate
                    break
                if not namespace:
                    break
                namespace = namespace.rsplit("/", 1)[0]
        if found is None:
            return [ERROR, f"Cannot find parameter [{key}] in an upwards search", ""]
        return [SUCCESS, f"Found [{found}]", found]

    def api_subscribe_param(self, caller_id: str, caller_api: str, key: str) -> Reply:
        name = resolve_key(key, caller_id)
        self._node(caller_id, caller_api)
        with self._lock:
            self._param_subscribers.setdefault(name, set()).add((caller_id, caller_api))
        value = _xmlrpc_value(self.params.get(name)) if self.params.has(name) else {}
        return [SUCCESS, f"Subscribed to parameter [{name}]", value]

    def api_unsubscribe_param(self, caller_id: str, caller_api: str, key: str) -> Reply:
        name = resolve_key(key, caller_id)
        with self._lock:
            had = (caller_id, caller_api) in self._param_subscribers.get(name, set())
            self._param_subscribers.get(name, set()).discard((caller_id, caller_api))
        return [SUCCESS, f"Unsubscribe to parameter [{name}]", int(had)]

    def _param_changed(self, name: str) -> None:
        """paramUpdate to whoever subscribed to ``name``, what is under it, or above it."""
        with self._lock:
            watched = [
                (key, who)
                for key, users in self._param_subscribers.items()
                for who in users
                if key == name
                or key.startswith(name.rstrip("/") + "/")
                or name.startswith(key + "/")
            ]
        for key, (_, api) in watched:
            value = _xmlrpc_value(self.params.get(key)) if self.params.has(key) else {}
            self._call_later(api, "paramUpdate", "/master", key, value)


def _related(a: str, b: str) -> bool:
    """Whether one parameter name is the other or in its namespace."""
    return a == b or a.startswith(b.rstrip("/") + "/") or b.startswith(a.rstrip("/") + "/")


def _snake(method: str) -> str:
    """``registerPublisher`` → ``register_publisher``."""
    return re.sub(r"(?<!^)([A-Z])", lambda m: "_" + m.group(1).lower(), method)


def _xmlrpc_value(value: Any) -> Any:
    """What XML-RPC can carry: None has no XML-RPC form (rosmaster's values never hold it)."""
    if value is None:
        return ""
    if isinstance(value, dict):
        return {str(k): _xmlrpc_value(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_xmlrpc_value(v) for v in value]
    if isinstance(value, bytes):
        return xmlrpc.client.Binary(value)
    return value
