"""The parameter service over Zenoh: the graph that holds the parameters answers the others'
requests (JSON under the key ``p``), as ROS 1's master serves its parameter server.

Binary values (XML-RPC's ``base64``, ``rosparam set -b``) are ``bytes`` in the tree; JSON
carries them as ``{"__bytes__": BASE64}``.
"""

from __future__ import annotations

import base64
import json
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph._errors import GraphError
from belvedere.graph._zenoh_session import TransportError, _Peer

__all__: list[str] = []


_BYTES = "__bytes__"


def _encode(value: Any) -> bytes:
    def binary(obj: object) -> dict[str, str]:
        if isinstance(obj, bytes):
            return {_BYTES: base64.b64encode(obj).decode("ascii")}
        msg = f"a parameter cannot hold a {type(obj).__name__}"
        raise TypeError(msg)

    return json.dumps(value, default=binary).encode()


def _decode(data: bytes) -> Any:
    def binary(obj: dict[str, Any]) -> Any:
        if len(obj) == 1 and isinstance(obj.get(_BYTES), str):
            return base64.b64decode(obj[_BYTES])
        return obj

    return json.loads(data, object_hook=binary)


class _ParamService(_Peer):
    """The transport's parameter service: answering, and asking the graph that answers."""

    # --- parameters ----------------------------------------------------------------------------
    def _on_param_query(self, query: Any) -> None:
        graph = self.graph
        assert graph is not None
        try:
            request = _decode(query.payload.to_bytes())
            op, name = request["op"], request.get("name", "/")
            params = graph.params
            if op == "get":
                value: Any = params.get(name)
            elif op == "set":
                params.set(name, request["value"])
                value = None
            elif op == "update":
                params.update(name, request["value"])
                value = None
            elif op == "delete":
                params.delete(name)
                value = None
            elif op == "has":
                value = params.has(name)
            elif op == "list":
                value = params.names(name)
            elif op == "load":
                params.load_yaml(request["yaml"], name, source=request.get("source", "<yaml>"))
                value = None
            elif op == "dump":
                value = params.dump_yaml(name)
            else:
                msg = f"unknown parameter operation {op!r}"
                raise TransportError(msg)
            reply = {"ok": True, "value": value}
        except BelvedereError as err:
            reply = {"ok": False, "error": err.message}
        except (KeyError, ValueError, TypeError) as err:
            reply = {"ok": False, "error": f"bad parameter request: {err}"}
        try:
            answer = _encode(reply)
        except TypeError as err:
            answer = _encode({"ok": False, "error": str(err)})
        query.reply(self._key("p"), answer)

    def param_request(self, request: dict[str, Any], timeout: float = 2.0) -> Any:
        """Ask the graph that holds the parameters (another process)."""
        replies = self.session.get(self._key("p"), payload=_encode(request), timeout=timeout)
        for reply in replies:
            if reply.ok is None:
                continue
            answer = _decode(reply.ok.payload.to_bytes())
            if not answer["ok"]:
                raise GraphError(answer["error"])
            return answer["value"]
        msg = "no running graph holds parameters (start a simulation or launch file first)"
        raise GraphError(msg)
