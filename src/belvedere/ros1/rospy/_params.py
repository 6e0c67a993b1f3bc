"""rospy's parameter functions against the graph's parameter server (another process: the
launch or run session, or a simulation), with ROS 1's XML-RPC value rules."""

from __future__ import annotations

from typing import Any, Final

from belvedere.errors import BelvedereError
from belvedere.ros1.rospy import _state
from belvedere.ros1.rospy._exceptions import ROSException

__all__ = [
    "delete_param",
    "get_param",
    "get_param_cached",
    "get_param_names",
    "has_param",
    "search_param",
    "set_param",
]

_MAXINT: Final = 2**31 - 1
_MININT: Final = -(2**31)
_UNSET: Final = object()


def _ask(request: dict[str, Any]) -> Any:
    runtime = _state.required()
    transport = runtime.transport
    try:
        if transport is None:
            return _local(runtime, request)
        return transport.param_request(request)
    except BelvedereError as err:
        raise ROSException(err.message) from None


def _local(runtime: _state.Runtime, request: dict[str, Any]) -> Any:
    params = runtime.graph.params
    op, name = request["op"], request["name"]
    if op == "get":
        return params.get(name)
    if op == "has":
        return params.has(name)
    if op == "set":
        params.set(name, request["value"])
    elif op == "delete":
        params.delete(name)
    elif op == "list":
        return params.names(name)
    return None


def _check_value(value: Any) -> Any:
    """What XML-RPC can carry, as rospy's client refuses the rest (ints are 32-bit)."""
    if isinstance(value, bool | str | float):
        return value
    if isinstance(value, int):
        if not _MININT <= value <= _MAXINT:
            msg = "int exceeds XML-RPC limits"
            raise OverflowError(msg)
        return value
    if value is None:
        msg = "cannot marshal None unless allow_none is enabled"
        raise TypeError(msg)
    if isinstance(value, list | tuple):
        return [_check_value(v) for v in value]
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                msg = "dictionary key must be string"
                raise TypeError(msg)
            out[key] = _check_value(item)
        return out
    msg = f"cannot marshal {type(value)} objects"
    raise TypeError(msg)


def get_param(param_name: str, default: Any = _UNSET) -> Any:
    resolved = _state.resolve(param_name)
    if not _ask({"op": "has", "name": resolved}):
        if default is _UNSET:
            raise KeyError(param_name)
        return default
    return _ask({"op": "get", "name": resolved})


get_param_cached = get_param


def set_param(param_name: str, param_value: Any) -> None:
    value = _check_value(param_value)
    _ask({"op": "set", "name": _state.resolve(param_name), "value": value})


def has_param(param_name: str) -> bool:
    return bool(_ask({"op": "has", "name": _state.resolve(param_name)}))


def delete_param(param_name: str) -> None:
    resolved = _state.resolve(param_name)
    if not _ask({"op": "has", "name": resolved}):
        raise KeyError(param_name)
    _ask({"op": "delete", "name": resolved})


def get_param_names() -> list[str]:
    names = _ask({"op": "list", "name": "/"})
    return [str(n) for n in names]


def search_param(param_name: str) -> str | None:
    """The nearest ``param_name`` up from the node (as ROS 1's parameter server searches:
    from the caller's own name to the root, on the name's first part), or None."""
    if param_name.startswith("/"):
        return param_name if has_param(param_name) else None
    if not param_name or param_name.startswith("~"):
        msg = "invalid key"
        raise ValueError(msg)
    head = next(p for p in param_name.split("/") if p)
    parts = [p for p in _state.caller_id().split("/") if p]
    while True:
        if has_param("/" + "/".join([*parts, head])):
            return "/" + "/".join([*parts, param_name.strip("/")])
        if not parts:
            return None
        parts.pop()
