"""Property scopes (lazy, chained) and the names every ``${}`` expression can use."""

from __future__ import annotations

import ast
import math
import re
from collections.abc import Callable, Iterator
from typing import Any, Final

from belvedere.description.xacro._errors import XacroError

__all__ = [
    "SAFE_BUILTINS",
    "NameSpace",
    "Scope",
    "YamlDict",
    "YamlList",
    "boolean",
    "kinetic_boolean",
    "kinetic_literal",
    "literal",
    "make_global_symbols",
]

TextEvaluator = Callable[[str, "Scope"], Any]


def literal(value: Any) -> Any:
    """xacro's typing of property values and macro arguments.

    ``'quoted'`` loses its quotes; anything with ``_`` stays text; then int, float and
    true/True/false/False are tried in that order.
    """
    if not isinstance(value, str):
        return value
    if len(value) >= 2 and value[0] == "'" and value[-1] == "'":
        return value[1:-1]
    if "_" in value or "$" in value:
        return value
    try:
        return int(value)
    except ValueError:
        pass
    try:
        return float(value)
    except ValueError:
        pass
    if value in ("true", "True"):
        return True
    if value in ("false", "False"):
        return False
    return value


def kinetic_literal(value: Any) -> Any:
    """ROS Kinetic's typing (Python 2 ``ast.literal_eval``): ``"true"`` stays text, ``0x10``
    is 16, ``007`` is octal; lists, tuples and dicts stay text."""
    if not isinstance(value, str) or "_" in value or "$" in value:
        return value
    text = value.strip()
    if re.fullmatch(r"[+-]?0[0-7]+", text):
        return int(text, 8)
    try:
        evaluated = ast.literal_eval(text)
    except (ValueError, SyntaxError, TypeError, MemoryError, RecursionError):
        return value
    if isinstance(evaluated, list | dict | tuple | set):
        return value
    return evaluated


def kinetic_boolean(value: Any, condition: str | None) -> bool:
    """ROS Kinetic's conditions also accept floats (``value="1.0"``)."""
    try:
        if isinstance(value, str) and value not in ("true", "True", "false", "False"):
            return bool(float(value))
    except ValueError:
        pass
    return boolean(value, condition)


def boolean(value: Any, condition: str | None) -> bool:
    """The truth of a condition value: true/True/false/False or anything ``int()`` accepts."""
    try:
        if isinstance(value, str):
            if value in ("true", "True"):
                return True
            if value in ("false", "False"):
                return False
            return bool(int(value))
        return bool(value)
    except (ValueError, TypeError):
        msg = (
            f'Xacro conditional "{condition}" evaluated to "{value}", '
            "which is not a boolean expression."
        )
        raise XacroError(msg, hint="use true/false, 1/0, or a ${} expression") from None


class Scope:
    """One level of properties: a macro call, an include namespace or the top level.

    Values are stored as text and evaluated on first use in the scope that defined them
    (lazy evaluation), then cached. Lookups walk up to the parent scopes, then the globals.
    """

    __slots__ = ("evaluate", "lazy", "literal", "parent", "resolving", "root", "vars")

    def __init__(
        self,
        parent: Scope | None,
        *,
        root: dict[str, Any] | None = None,
        evaluate: TextEvaluator | None = None,
        typing: Callable[[Any], Any] = literal,
    ) -> None:
        self.parent = parent
        self.vars: dict[str, Any] = {}
        self.lazy: set[str] = set()
        self.resolving: list[str] = []
        if parent is not None:
            self.root: dict[str, Any] = parent.root
            self.evaluate: TextEvaluator | None = parent.evaluate
            self.literal: Callable[[Any], Any] = parent.literal
        else:
            self.root = {} if root is None else root
            self.evaluate = evaluate
            self.literal = typing

    # --- lookup ----------------------------------------------------------------------------
    def __getitem__(self, key: str) -> Any:
        s: Scope | None = self
        while s is not None:
            v = s.vars.get(key, _MISSING)
            if v is not _MISSING:
                if s.lazy and key in s.lazy:
                    return s._resolve(key)
                return v
            s = s.parent
        return self.root[key]

    def __contains__(self, key: object) -> bool:
        s: Scope | None = self
        while s is not None:
            if key in s.vars:
                return True
            s = s.parent
        return key in self.root

    def _resolve(self, key: str) -> Any:
        if key in self.resolving:
            chain = " -> ".join([*self.resolving, key])
            msg = f"circular variable definition: {chain}"
            raise XacroError(msg, hint='consider disabling lazy evaluation via lazy_eval="false"')
        assert self.evaluate is not None
        self.resolving.append(key)
        try:
            value = self.literal(self.evaluate(self.vars[key], self))
        finally:
            self.resolving.pop()
        self.vars[key] = value
        self.lazy.discard(key)
        return value

    # --- definition ------------------------------------------------------------------------
    def define(self, key: str, value: Any, *, lazy: bool) -> None:
        """Store ``value`` (typed like a literal); text stays unevaluated when ``lazy``."""
        value = self.literal(value)
        self.vars[key] = value
        if lazy and isinstance(value, str):
            self.lazy.add(key)
        else:
            self.lazy.discard(key)

    def remove(self, key: str) -> None:
        """Remove ``key`` from this scope and every parent."""
        s: Scope | None = self
        while s is not None:
            s.vars.pop(key, None)
            s.lazy.discard(key)
            s = s.parent

    def top(self) -> Scope:
        """The top-level scope (the document's own, below the globals)."""
        s = self
        while s.parent is not None:
            s = s.parent
        return s


_MISSING: Final = object()


class NameSpace(Scope):
    """A scope reachable by dotted access: ``${ns.prop}`` (include namespaces, ``math``…)."""

    __slots__ = ()

    def __getattr__(self, item: str) -> Any:
        try:
            return self[item]
        except KeyError:
            msg = f"name '{item}' is not defined"
            raise NameError(msg) from None

    def __repr__(self) -> str:
        return repr(self.vars)


# --- YAML values -------------------------------------------------------------------------------


def _wrap(item: Any) -> Any:
    if isinstance(item, dict) and not isinstance(item, YamlDict):
        return YamlDict(item)
    if isinstance(item, list) and not isinstance(item, YamlList):
        return YamlList(item)
    return item


class YamlList(list[Any]):
    """A YAML list whose nested dicts allow dotted access."""

    def __getitem__(self, idx: Any) -> Any:
        return _wrap(super().__getitem__(idx))

    def __iter__(self) -> Iterator[Any]:
        for item in super().__iter__():
            yield _wrap(item)


class YamlDict(dict[Any, Any]):
    """A YAML mapping with dotted access: ``${cfg.arm.length}``."""

    def __getattr__(self, item: str) -> Any:
        try:
            return _wrap(super().__getitem__(item))
        except KeyError:
            msg = f"The yaml dictionary has no key '{item}'"
            raise AttributeError(msg) from None

    __getitem__ = __getattr__


# --- the global names ------------------------------------------------------------------------

_BUILTINS: Final[dict[str, Any]] = {
    "list": list,
    "dict": dict,
    "map": map,
    "len": len,
    "str": str,
    "float": float,
    "int": int,
    "bool": bool,
    "True": True,
    "False": False,
    "min": min,
    "max": max,
    "round": round,
}
_PYTHON_EXTRA: Final[dict[str, Any]] = {
    "abs": abs,
    "all": all,
    "any": any,
    "complex": complex,
    "divmod": divmod,
    "enumerate": enumerate,
    "filter": filter,
    "frozenset": frozenset,
    "hash": hash,
    "isinstance": isinstance,
    "issubclass": issubclass,
    "ord": ord,
    "repr": repr,
    "reversed": reversed,
    "slice": slice,
    "set": set,
    "sum": sum,
    "tuple": tuple,
    "type": type,
    "vars": vars,
    "zip": zip,
    "sorted": sorted,
    "range": range,
}


SAFE_BUILTINS: Final[dict[str, Any]] = {**_BUILTINS, **_PYTHON_EXTRA}
"""Builtins with no access to files, the interpreter or attributes by name."""


def tokenize_string(s: str, sep: str = ",; ", skip_empty: bool = True) -> list[str]:
    """``xacro.tokenize``: split on any of the separator characters."""
    parts = re.split(f"[{sep}]", s)
    return [p for p in parts if p] if skip_empty else parts


def make_global_symbols(
    *,
    warn: Callable[[str], None],
    xacro_functions: dict[str, Any],
) -> dict[str, Any]:
    """The names every expression sees, as xacro 2.1.1 exposes them.

    ``xacro_functions`` are the per-run functions (``load_yaml``, ``arg``, ``message``…).
    """

    def deprecated(name: str, ns: str, f: Callable[..., Any]) -> Callable[..., Any]:
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            warn(f"Using {name}() directly is deprecated. Use {ns}.{name}() instead.")
            return f(*args, **kwargs)

        return wrapper

    symbols: dict[str, Any] = dict(_BUILTINS)
    python = NameSpace(None)
    python.vars.update(SAFE_BUILTINS)
    symbols["python"] = python
    for name in ("sorted", "range"):
        symbols[name] = deprecated(name, "python", _PYTHON_EXTRA[name])

    math_ns = NameSpace(None)
    for k, v in vars(math).items():
        if not k.startswith("_"):
            math_ns.vars[k] = v
            symbols[k] = v
    symbols["math"] = math_ns

    xacro_ns = NameSpace(None)
    xacro_ns.vars.update(xacro_functions)
    xacro_ns.vars["tokenize"] = tokenize_string
    symbols["xacro"] = xacro_ns
    for name in ("load_yaml", "abs_filename", "dotify"):
        symbols[name] = deprecated(name, "xacro", xacro_functions[name])
    return symbols
