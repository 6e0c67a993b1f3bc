"""A running ROS 1 master (a robot's, Debian's roscore) that the graph joins: the bridge
registers the graph's publishers, subscribers and services there under its own node name and
slave API, as one ROS 1 node, and learns the ROS 1 publishers of the topics the graph
subscribes to from ``registerSubscriber`` and ``publisherUpdate``."""

from __future__ import annotations

import logging
import threading
import time
import xmlrpc.client
from typing import Any, Final

from belvedere.errors import BelvedereError
from belvedere.ros1wire._master import Peers, Registrations
from belvedere.ros1wire._xmlrpc import server_proxy

__all__ = ["RemoteMaster", "RemoteMasterError"]

logger = logging.getLogger("belvedere.ros1wire")

LOOK_S: Final = 1.0
"""How often the master's topics and services are looked at (it tells nobody of them)."""


class RemoteMasterError(BelvedereError):
    """The master does not answer, or refused a registration."""


class RemoteMaster:
    def __init__(self, uri: str) -> None:
        self.uri = uri if uri.endswith("/") else uri + "/"
        self._lock = threading.Lock()
        self._ros1 = Registrations()
        self._peers: Any = None
        self._services_at = 0.0
        self._topic_types: dict[str, str] = {}
        """topic → the type the graph subscribes to it with"""
        self._node_apis: dict[str, str] = {}
        try:
            self._call("getUri")
        except RemoteMasterError as err:
            msg = f"cannot reach the ROS 1 master at {self.uri}: {err.message}"
            raise RemoteMasterError(msg, hint="is roscore running there?") from None

    @property
    def caller_id(self) -> str:
        return str(self._peers.caller_id) if self._peers is not None else "/belvedere"

    def _call(self, method: str, *args: Any) -> Any:
        try:
            code, status, value = getattr(server_proxy(self.uri, timeout=5.0), method)(
                self.caller_id, *args
            )
        except (OSError, xmlrpc.client.Error) as err:
            raise RemoteMasterError(str(err)) from None
        if code != 1:
            msg = f"{method}: {status}"
            raise RemoteMasterError(msg)
        return value

    # --- MasterSide ------------------------------------------------------------------------------
    def attach(self, peers: Peers) -> None:
        self._peers = peers

    def ros1_view(self) -> Registrations:
        with self._lock:
            return self._ros1.copy()

    def publishers_updated(self, topic: str, uris: list[str]) -> None:
        own = self._peers.uri if self._peers is not None else None
        with self._lock:
            typ = self._topic_types.get(topic, "*")
            users = {u: typ for u in uris if u != own}
            if users:
                self._ros1.publishers[topic] = users
            else:
                self._ros1.publishers.pop(topic, None)
            for u in users:
                self._ros1.nodes[u] = u

    def graph_changed(self, before: Registrations, after: Registrations) -> None:
        peers = self._peers
        if peers is None:
            return
        api = peers.uri
        try:
            for topic in set(after.publishers) - set(before.publishers):
                self._call("registerPublisher", topic, _type(after.publishers[topic]), api)
            for topic in set(before.publishers) - set(after.publishers):
                self._call("unregisterPublisher", topic, api)
            for topic in set(after.subscribers) - set(before.subscribers):
                typ = _type(after.subscribers[topic])
                self._topic_types[topic] = typ
                uris = self._call("registerSubscriber", topic, typ, api)
                self.publishers_updated(topic, [str(u) for u in uris])
            for topic in set(before.subscribers) - set(after.subscribers):
                self._call("unregisterSubscriber", topic, api)
                self._topic_types.pop(topic, None)
                self.publishers_updated(topic, [])
            rosrpc = peers.service_uri()
            for service in set(after.services) - set(before.services):
                self._call("registerService", service, rosrpc, api)
            for service in set(before.services) - set(after.services):
                self._call("unregisterService", service, rosrpc)
            if time.monotonic() >= self._services_at:
                self._services_at = time.monotonic() + LOOK_S
                self._look_at_master(after, rosrpc)
        except RemoteMasterError as err:
            logger.warning("ros1: the master at %s: %s", self.uri, err.message)

    def _look_at_master(self, graph: Registrations, own: str) -> None:
        """The ROS 1 programs' topics and services (not the graph's, registered by us): the
        topics are advertised on the graph, the services offered there."""
        publishers, _, services = self._call("getSystemState")
        types = {str(t): str(typ) for t, typ in self._call("getTopicTypes")}
        me = self.caller_id
        found: dict[str, dict[str, str]] = {}
        for name, providers in services:
            if name in graph.services or not providers:
                continue
            uri = str(self._call("lookupService", name))
            if uri != own:
                found[str(name)] = {str(providers[0]): uri}
        listed: dict[str, dict[str, str]] = {}
        for topic, nodes in publishers:
            others = [str(n) for n in nodes if n != me]
            if others and str(topic) not in self._topic_types:
                listed[str(topic)] = {n: types.get(str(topic), "*") for n in others}
        apis = {}
        for users in listed.values():
            for node in users:
                if node not in self._node_apis:
                    self._node_apis[node] = str(self._call("lookupNode", node))
                apis[node] = self._node_apis[node]
        with self._lock:
            self._ros1.services = found
            for topic in [t for t in self._ros1.publishers if t not in self._topic_types]:
                del self._ros1.publishers[topic]
            self._ros1.publishers.update(listed)
            self._ros1.nodes.update(apis)

    def params(self) -> Any:
        """The master's parameter tree (a robot's robot_description, its configuration)."""
        try:
            return self._call("getParam", "/")
        except RemoteMasterError as err:
            logger.warning("ros1: cannot read the master's parameters: %s", err.message)
            return {}

    def close(self) -> None:
        """Unregister what the graph had registered (as a ROS 1 node does when it ends)."""
        peers = self._peers
        if peers is None:
            return
        self.graph_changed(peers.graph_state(), Registrations())


def _type(users: dict[str, str]) -> str:
    return next(iter(users.values()), "*")
