"""Property scopes (lazy, chained) and the names every ``${}`` expression can use."""

from __future__ import annotations

import ast
import re
from collections.abc import Callable
from typing import Any, Final

from belvedere.description.xacro._builtins import (
    Namespace,
    expose,
    math_functions,
    python_functions,
)
from belvedere.description.xacro._errors import XacroError
from belvedere.errors import SourceLocation

__all__ = [
    "NameSpace",
    "Scope",
    "boolean",
    "kinetic_boolean",
    "kinetic_literal",
    "literal",
    "make_global_symbols",
]

TextEvaluator = Callable[[str, "Scope", str, "SourceLocation | None"], Any]
"""Evaluates a lazy property's text: (text, scope, property name, where it was defined)."""


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
        self.lazy: dict[str, SourceLocation | None] = {}
        """Properties still stored as text, and where each was defined."""
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
            value = self.literal(self.evaluate(self.vars[key], self, key, self.lazy[key]))
        finally:
            self.resolving.pop()
        self.vars[key] = value
        self.lazy.pop(key, None)
        return value

    # --- definition ------------------------------------------------------------------------
    def define(
        self, key: str, value: Any, *, lazy: bool, where: SourceLocation | None = None
    ) -> None:
        """Store ``value`` (typed like a literal); text stays unevaluated when ``lazy``
        (``where`` it was defined is kept for errors found when it is evaluated)."""
        value = self.literal(value)
        self.vars[key] = value
        if lazy and isinstance(value, str):
            self.lazy[key] = where
        else:
            self.lazy.pop(key, None)

    def remove(self, key: str) -> None:
        """Remove ``key`` from this scope and every parent."""
        s: Scope | None = self
        while s is not None:
            s.vars.pop(key, None)
            s.lazy.pop(key, None)
            s = s.parent

    def top(self) -> Scope:
        """The top-level scope (the document's own, below the globals)."""
        s = self
        while s.parent is not None:
            s = s.parent
        return s


_MISSING: Final = object()


class NameSpace(Scope, Namespace):
    """A scope reachable by dotted access: ``${ns.prop}`` (include namespaces, ``math``…)."""

    __slots__ = ()

    def __repr__(self) -> str:
        return repr(self.vars)


# --- the global names ------------------------------------------------------------------------

_BARE: Final = [
    "list",
    "dict",
    "map",
    "len",
    "str",
    "float",
    "int",
    "bool",
    "True",
    "False",
    "min",
    "max",
    "round",
]
"""The builtins xacro has always exposed without the ``python.`` prefix."""


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

        return expose(wrapper, name)

    builtins = python_functions()
    symbols: dict[str, Any] = {name: builtins[name] for name in _BARE}
    python = NameSpace(None)
    python.vars.update(builtins)
    symbols["python"] = python
    for name in ("sorted", "range"):
        symbols[name] = deprecated(name, "python", builtins[name])

    math_ns = NameSpace(None)
    math_ns.vars.update(math_functions())
    symbols.update(math_ns.vars)
    symbols["math"] = math_ns

    xacro_ns = NameSpace(None)
    xacro_ns.vars.update({k: expose(f, k) for k, f in xacro_functions.items()})
    xacro_ns.vars["tokenize"] = expose(tokenize_string, "tokenize")
    symbols["xacro"] = xacro_ns
    for name in ("load_yaml", "abs_filename", "dotify"):
        symbols[name] = deprecated(name, "xacro", xacro_functions[name])
    return symbols
