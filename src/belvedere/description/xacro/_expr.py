"""Text with ``${expr}`` / ``$(cmd …)`` in it: the lexer and the sandboxed evaluator.

The lexer splits text exactly as xacro 2.1.1 does (``${…}`` cannot contain ``}``, ``$(…)``
cannot contain ``)``, ``$$`` escapes). Expressions are Python, compiled once per distinct
string and checked on the syntax tree: no name or attribute may start with ``__`` anywhere
(also inside lambdas and comprehensions), and ``str.format`` cannot reach attributes that
start with ``_``. Builtins are empty; only the names the scope provides exist.
"""

from __future__ import annotations

import ast
import contextlib
import re
import string
from collections.abc import Mapping
from functools import partial
from types import CodeType
from typing import Any, Final, Protocol, cast

from belvedere.description.xacro._errors import XacroError
from belvedere.errors import BelvedereError

__all__ = ["TEXT", "ExpressionError", "Token", "compile_expr", "eval_code", "evaluate", "tokenize"]

TEXT: Final = 0
EXPR: Final = 1
EXTENSION: Final = 2

Token = tuple[int, str]
"""(kind, payload): TEXT → literal text, EXPR → the inside of ``${}``, EXTENSION → of ``$()``."""

_LEXER: Final = re.compile(
    r"(?P<dollars>\$\$+[{(])|(?P<expr>\$\{[^}]*\})|(?P<ext>\$\([^)]*\))|(?P<text>[^$]+|\$[^{($]+|\$$)"
)
_token_cache: dict[str, tuple[Token, ...]] = {}


def tokenize(text: str) -> tuple[Token, ...]:
    """Split ``text`` into tokens (cached: the same strings recur in every macro call)."""
    toks = _token_cache.get(text)
    if toks is not None:
        return toks
    out: list[Token] = []
    pos = 0
    n = len(text)
    match = _LEXER.match
    while pos < n:
        m = match(text, pos)
        if m is None:
            msg = f"invalid expression: {text[pos:]}"
            raise XacroError(msg, hint="'${' needs a closing '}' and '$(' a closing ')'")
        kind = m.lastgroup
        tok = m.group()
        if kind == "expr":
            out.append((EXPR, tok[2:-1]))
        elif kind == "ext":
            out.append((EXTENSION, tok[2:-1]))
        elif kind == "dollars":
            out.append((TEXT, tok[1:]))
        else:
            out.append((TEXT, tok))
        pos = m.end()
    result = tuple(out)
    if len(_token_cache) < 200_000:
        _token_cache[text] = result
    return result


# --- the sandbox ---------------------------------------------------------------------------


class _SafeFormatter(string.Formatter):
    def get_field(self, field_name: str, args: Any, kwargs: Any) -> Any:
        if "._" in field_name or "[_" in field_name or field_name.startswith("_"):
            msg = f"format field {field_name!r} is not allowed (names starting with '_')"
            raise XacroError(msg)
        return super().get_field(field_name, args, kwargs)


_FORMATTER: Final = _SafeFormatter()


def _format_attr(obj: Any, name: str) -> Any:
    """``obj.format`` / ``obj.format_map`` with a formatter that cannot reach private names."""
    if isinstance(obj, str):
        if name == "format":
            return partial(_FORMATTER.format, obj)
        return lambda mapping: _FORMATTER.vformat(obj, (), mapping)
    return getattr(obj, name)


_FORMAT_HELPER: Final = "__bv_format_attr"


class _Rewrite(ast.NodeTransformer):
    def visit_Attribute(self, node: ast.Attribute) -> ast.AST:
        self.generic_visit(node)
        if node.attr in ("format", "format_map") and isinstance(node.ctx, ast.Load):
            call = ast.Call(
                func=ast.Name(_FORMAT_HELPER, ast.Load()),
                args=[node.value, ast.Constant(node.attr)],
                keywords=[],
            )
            return ast.copy_location(call, node)
        return node


def _forbidden_names(tree: ast.AST) -> list[str]:
    bad: list[str] = []
    for node in ast.walk(tree):
        name = None
        if isinstance(node, ast.Name):
            name = node.id
        elif isinstance(node, ast.Attribute):
            name = node.attr
        elif isinstance(node, ast.arg | ast.keyword):
            name = node.arg
        if name is not None and name.startswith("__") and name not in bad:
            bad.append(name)
    return bad


class Compiled:
    """A checked, compiled expression."""

    __slots__ = ("code", "nested_names")

    def __init__(self, code: CodeType, nested_names: tuple[str, ...]) -> None:
        self.code = code
        self.nested_names = nested_names
        """Names used inside lambdas/comprehensions (looked up as globals by Python)."""


_compile_cache: dict[str, Compiled] = {}


def _nested_names(code: CodeType) -> list[str]:
    names: list[str] = []
    for const in code.co_consts:
        if isinstance(const, CodeType):
            names.extend(const.co_names)
            names.extend(_nested_names(const))
    return names


def compile_expr(expr: str) -> Compiled:
    """Compile one ``${}`` expression, refusing private names."""
    hit = _compile_cache.get(expr)
    if hit is not None:
        return hit
    source = expr.strip()
    try:
        tree = ast.parse(source, "<expression>", "eval")
    except SyntaxError as err:
        caret = ""
        if err.offset and err.lineno == 1:
            caret = "\n    " + source + "\n    " + " " * (err.offset - 1) + "^"
        msg = f"invalid expression '{expr}': {err.msg}{caret}"
        raise XacroError(msg) from None
    bad = _forbidden_names(tree)
    if bad:
        msg = f"use of invalid name(s) in '{expr}': {', '.join(bad)}"
        raise XacroError(msg, hint="names starting with '__' are not available in xacro")
    tree = ast.fix_missing_locations(_Rewrite().visit(tree))
    code = compile(tree, "<expression>", "eval")
    compiled = Compiled(code, tuple(dict.fromkeys(_nested_names(code))))
    if len(_compile_cache) < 200_000:
        _compile_cache[expr] = compiled
    return compiled


_PLAIN_GLOBALS: Final[dict[str, Any]] = {"__builtins__": {}, _FORMAT_HELPER: _format_attr}


class Lookup(Protocol):
    """What an expression reads its names from (a property scope)."""

    def __getitem__(self, key: str, /) -> Any: ...


def eval_code(compiled: Compiled, scope: Lookup) -> Any:
    """Evaluate in ``scope`` (a mapping with lazy lookups) with no builtins."""
    if not compiled.nested_names:
        return eval(compiled.code, _PLAIN_GLOBALS, cast(Mapping[str, Any], scope))
    # Python looks names up as globals inside lambdas and comprehensions: give them the
    # names they use, resolved from the scope now.
    env: dict[str, Any] = dict(_PLAIN_GLOBALS)
    for name in compiled.nested_names:
        # Misses are attribute names or the comprehension's own locals.
        with contextlib.suppress(KeyError, XacroError):
            env[name] = scope[name]
    return eval(compiled.code, env, cast(Mapping[str, Any], scope))


class ExpressionError(XacroError):
    """An expression that raised when evaluated; ``cause`` is what Python raised."""

    def __init__(self, expr: str, cause: Exception) -> None:
        if isinstance(cause, NameError):
            msg = f"{cause} when evaluating expression '{expr}'"
        else:
            msg = f"{type(cause).__name__}: {cause} when evaluating expression '{expr}'"
        super().__init__(msg)
        self.cause = cause


def evaluate(expr: str, scope: Lookup) -> Any:
    """Compile (cached) and evaluate one expression; whatever it raises becomes an error
    that names the expression."""
    compiled = compile_expr(expr)
    try:
        return eval_code(compiled, scope)
    except (BelvedereError, RecursionError):
        raise
    except Exception as err:  # noqa: BLE001 (user expressions may raise anything)
        raise ExpressionError(expr, err) from None
