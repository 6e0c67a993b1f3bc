"""Asking a node in another process: ``ping`` (its process answers: rosnode ping's round
trip, which in ROS 1 is an XML-RPC call to the node) and ``kill`` (the node is shut down
there, as rosnode kill asks a ROS 1 node: a rospy script runs its shutdown hooks and ends).

Each process answers for its own nodes on the key ``c/<node>`` (JSON).
"""

from __future__ import annotations

import json
import os
import socket
from typing import Any

import zenoh

from belvedere.graph._graph import Node
from belvedere.graph._zenoh_session import _Peer, decode_key, encode_key

__all__: list[str] = []


class _NodeControl(_Peer):
    """The transport's answers to requests to its own nodes, and its requests to others'."""

    _own_nodes: dict[str, tuple[int, Node]]

    def _on_control_query(self, query: Any) -> None:
        name = str(query.key_expr).removeprefix(self._key("c/"))
        with self._lock:
            mine = self._own_nodes.get(decode_key(name))
        if mine is None:
            return  # another process's node (or none): it answers, not this one
        node = mine[1]
        try:
            request = json.loads(query.payload.to_bytes()) if query.payload else {}
        except ValueError:
            request = {}
        op = request.get("op") if isinstance(request, dict) else None
        if op == "kill":
            node.shutdown_request = (str(request.get("caller", "")), "user request")
            graph = self.graph
            if graph is not None:
                graph.executor.post(node.shutdown)
        reply = {"node": node.full_name, "pid": os.getpid(), "host": socket.gethostname()}
        query.reply(query.key_expr, json.dumps(reply).encode())

    def node_request(
        self, node: str, op: str, *, caller: str = "", timeout: float = 2.0
    ) -> dict[str, Any] | None:
        """Ask the process that holds ``node`` (``ping`` or ``kill``); its answer (the node,
        its process's pid and host), or None when no process answers within ``timeout``."""
        payload = json.dumps({"op": op, "caller": caller}).encode()
        key = self._key("c/", encode_key(node))
        # every process's queryable is asked (the default asks only the "best" one)
        replies = self.session.get(
            key, payload=payload, timeout=timeout, target=zenoh.QueryTarget.ALL
        )
        for reply in replies:
            if reply.ok is not None:
                answer: dict[str, Any] = json.loads(reply.ok.payload.to_bytes())
                return answer
        return None
