"""The parameter tree, as ROS 1's parameter server keeps it.

Names are hierarchical (``/move_base/local_costmap/width``); getting a namespace returns a
dictionary of everything below it; setting a dictionary sets every leaf. Values keep their
YAML types (int, float, bool, str, list, dict).
"""

from __future__ import annotations

import copy
from typing import Any

import yaml

from belvedere.errors import BelvedereError
from belvedere.yamlfile import load_yaml

__all__ = ["ParamError", "ParamTree", "leaves"]


class ParamError(BelvedereError):
    """A missing parameter or a bad parameter name."""


def _parts(name: str) -> list[str]:
    if not name.startswith("/"):
        msg = f"parameter name {name!r} is not resolved (must start with '/')"
        raise ParamError(msg)
    return [p for p in name.split("/") if p]


class ParamTree:
    """Hierarchical parameters."""

    def __init__(self) -> None:
        self._root: dict[str, Any] = {}
        self.version = 0
        """Bumped on every change (watchers compare it)."""

    def get(self, name: str, default: Any = ...) -> Any:
        node: Any = self._root
        for part in _parts(name):
            if not isinstance(node, dict) or part not in node:
                if default is not ...:
                    return default
                near = self._near(name)
                msg = f"parameter {name!r} is not set" + (f" (near: {near})" if near else "")
                raise ParamError(msg)
            node = node[part]
        return copy.deepcopy(node)

    def has(self, name: str) -> bool:
        return self.get(name, _ABSENT) is not _ABSENT

    def set(self, name: str, value: Any) -> None:
        parts = _parts(name)
        if not parts:
            if not isinstance(value, dict):
                msg = "only a dictionary can be set at the root '/'"
                raise ParamError(msg)
            self._root = copy.deepcopy(value)
        else:
            node = self._root
            for part in parts[:-1]:
                child = node.get(part)
                if not isinstance(child, dict):
                    child = node[part] = {}
                node = child
            node[parts[-1]] = copy.deepcopy(value)
        self.version += 1

    def update(self, name: str, value: Any) -> None:
        """rosparam's ``set`` and ``load``: a dictionary sets each leaf below ``name`` and
        keeps what it does not name (ROS's #1098: an update, not a replacement, so an empty
        dictionary sets nothing); anything else is set as :meth:`set` does."""
        for leaf, leaf_value in leaves(name, value):
            self.set(leaf, leaf_value)

    def delete(self, name: str) -> None:
        parts = _parts(name)
        node: Any = self._root
        for part in parts[:-1]:
            if not isinstance(node, dict) or part not in node:
                msg = f"parameter {name!r} is not set"
                raise ParamError(msg)
            node = node[part]
        if not parts or not isinstance(node, dict) or parts[-1] not in node:
            msg = f"parameter {name!r} is not set"
            raise ParamError(msg)
        del node[parts[-1]]
        self.version += 1

    def names(self, namespace: str = "/") -> list[str]:
        """Every leaf parameter name at or under ``namespace``, sorted."""
        out: list[str] = []

        def walk(node: Any, prefix: str) -> None:
            if isinstance(node, dict) and node:
                for key in sorted(node):
                    walk(node[key], f"{prefix}/{key}")
            else:
                out.append(prefix or "/")

        base = self.get(namespace, None) if namespace != "/" else self._root
        if base is None:
            return []
        walk(base, namespace.rstrip("/"))
        return out

    def load_yaml(self, text: str, namespace: str = "/", *, source: str = "<yaml>") -> None:
        """``rosparam load``: set everything in a YAML mapping under ``namespace``."""
        data = load_yaml(text, path=source).data
        if data is None:
            return
        if not isinstance(data, dict):
            if namespace == "/":
                msg = f"{source}: parameters at the root must be a mapping"
                raise ParamError(msg)
            self.set(namespace, data)
            return
        for key, value in data.items():
            self.set(f"{namespace.rstrip('/')}/{key}", value)

    def dump_yaml(self, namespace: str = "/") -> str:
        """``rosparam dump``."""
        data = self._root if namespace == "/" else self.get(namespace)
        return yaml.safe_dump(data, default_flow_style=False, sort_keys=True)

    def _near(self, name: str) -> str:
        import difflib

        close = difflib.get_close_matches(name, self.names(), n=3)
        return ", ".join(close)


def leaves(name: str, value: Any) -> list[tuple[str, Any]]:
    """The (name, value) pairs rosparam sets for ``value`` at ``name``, in its order: each
    leaf of a dictionary, or the value itself. ROS's parameter server has no null, so a null
    (YAML ``~`` or nothing) is refused as rosparam's server refuses it."""
    if isinstance(value, dict):
        out: list[tuple[str, Any]] = []
        for key, child in value.items():
            if not isinstance(key, str):
                msg = f"YAML dictionaries must have string keys, not {key!r}"
                raise ParamError(msg)
            out += leaves(f"{name.rstrip('/')}/{key}", child)
        return out
    if name == "/":
        msg = "global / can only be set to a dictionary"
        raise ParamError(msg)
    if value is None:
        msg = f"{name}: the parameter server has no null value (write '' for an empty string)"
        raise ParamError(msg)
    return [(name, value)]


class _Absent:
    pass


_ABSENT = _Absent()
