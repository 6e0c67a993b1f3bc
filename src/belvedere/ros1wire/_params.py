"""The graph's parameters as the ROS 1 master serves them: in this process's tree when this
process holds them (``belvedere roscore`` alone), else asked of the process that does."""

from __future__ import annotations

from typing import Any

from belvedere.graph import Graph, ParamError, ZenohTransport

__all__ = ["GraphParams", "resolve_key"]


class GraphParams:
    def __init__(self, graph: Graph) -> None:
        self.graph = graph
        transport = graph.transport
        self._remote = isinstance(transport, ZenohTransport) and not transport.serve_params

    def _ask(self, op: str, name: str, **more: Any) -> Any:
        transport = self.graph.transport
        assert isinstance(transport, ZenohTransport)
        return transport.param_request({"op": op, "name": name, **more})

    def get(self, name: str) -> Any:
        """The value (a namespace: a dict); raises ParamError when unset."""
        if self._remote:
            if not self._ask("has", name):
                msg = f"parameter {name!r} is not set"
                raise ParamError(msg)
            return self._ask("get", name)
        return self.graph.params.get(name)

    def has(self, name: str) -> bool:
        return bool(self._ask("has", name)) if self._remote else self.graph.params.has(name)

    def set(self, name: str, value: Any) -> None:
        if self._remote:
            self._ask("set", name, value=value)
        else:
            self.graph.params.set(name, value)

    def delete(self, name: str) -> None:
        if self._remote:
            self._ask("delete", name)
        else:
            self.graph.params.delete(name)

    def names(self) -> list[str]:
        """Every leaf's name (rosmaster's getParamNames lists no namespaces)."""
        tree = self.get("/") if self._remote else self.graph.params.get("/")
        out: list[str] = []

        def walk(node: Any, prefix: str) -> None:
            for key in sorted(node):
                name = f"{prefix}/{key}"
                if isinstance(node[key], dict) and node[key]:
                    walk(node[key], name)
                else:
                    out.append(name)

        if isinstance(tree, dict):
            walk(tree, "")
        return out


def resolve_key(key: str, caller_id: str) -> str:
    """A parameter name as the master resolves it: relative to the caller's namespace,
    ``~name`` in the caller's own."""
    if key.startswith("/"):
        resolved = key
    elif key.startswith("~"):
        resolved = f"{caller_id.rstrip('/')}/{key[1:]}"
    else:
        namespace = caller_id.rsplit("/", 1)[0] if "/" in caller_id else ""
        resolved = f"{namespace}/{key}"
    while "//" in resolved:
        resolved = resolved.replace("//", "/")
    if len(resolved) > 1:
        resolved = resolved.rstrip("/")
    return resolved or "/"
