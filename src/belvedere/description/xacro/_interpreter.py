"""The expression language of ``${…}`` and ``$(eval …)``: Python's expression syntax, run by an
interpreter of our own.

xacro and roslaunch hand expressions to Python's ``eval``. Whatever a name check refuses, a
value that reaches Python's object model (``vars(type)``, ``str.format``'s field syntax, a
generator's frame) leads back to the interpreter's internals and from there to running code.
So nothing here is evaluated by Python: the parsed syntax tree is compiled into a tree of
closures that allow only what xacro documents —

- numbers, strings, lists, tuples, dicts, sets, f-strings;
- arithmetic, comparisons, boolean operators, conditional expressions, indexing and slicing,
  comprehensions and lambdas (their variables are ours, not Python's);
- calls of an explicit list of functions (the builtins xacro lists, ``math.*``, the
  ``xacro.*`` helpers) and of lambdas written in the expression;
- attribute access only on values we made: YAML data (``cfg.arm.length``), namespaces
  (``math.pi``, ``xacro.load_yaml``, an include's ``ns.prop``) and a list of string, list,
  dict and number methods. ``str.format`` fields are plain names or positions.

Work is bounded: integers stay below :data:`MAX_INT_BITS`, strings below :data:`MAX_CHARS`,
ranges below :data:`MAX_ITEMS`, nested values below :data:`MAX_WEIGHT` elements (repeating a
list of lists multiplies what printing or comparing it costs), iteration inside builtins and
comprehensions below :data:`MAX_STEPS`, syntax nesting below :data:`MAX_DEPTH` and lambda calls
below :data:`MAX_CALLS`. Each refusal is one :class:`ExpressionError` naming the construct and
its column in the expression.
"""

from __future__ import annotations

import ast
import warnings
from typing import Any, Final, Protocol

from belvedere.description.xacro._bounds import MAX_DEPTH, RefusedError, budget
from belvedere.description.xacro._builtins import Code
from belvedere.description.xacro._compiler import Compiler
from belvedere.description.xacro._errors import XacroError
from belvedere.errors import BelvedereError

__all__ = ["Compiled", "ExpressionError", "Lookup", "compile_expr", "evaluate"]


class Lookup(Protocol):
    """Where an expression reads its names (a property scope, or a dict)."""

    def __getitem__(self, key: str, /) -> Any: ...


# --- errors ------------------------------------------------------------------------------------


class ExpressionError(XacroError):
    """An expression that was refused or that raised.

    ``cause`` is the Python exception it raised (None for a refusal); ``offset`` is where in
    the expression the refused construct starts (0-based), when known.
    """

    def __init__(
        self,
        expr: str,
        message: str,
        *,
        cause: Exception | None = None,
        offset: int | None = None,
        hint: str | None = None,
    ) -> None:
        if offset is not None:
            source = expr.strip()
            lead = len(expr) - len(expr.lstrip())
            pointer = max(0, offset - lead)
            message = f"{message}\n    {source}\n    {' ' * pointer}^"
        super().__init__(message, hint=hint)
        self.expr = expr
        self.cause = cause
        self.offset = offset

    @classmethod
    def raised(cls, expr: str, cause: Exception) -> ExpressionError:
        """The error for an exception the expression raised (xacro's wording)."""
        if isinstance(cause, NameError):
            return cls(expr, f"{cause} when evaluating expression '{expr}'", cause=cause)
        text = f"{type(cause).__name__}: {cause} when evaluating expression '{expr}'"
        return cls(expr, text, cause=cause)


# --- compiled expressions (the compiler: _compiler.py) -------------------------------------------


class Compiled:
    """One compiled expression."""

    __slots__ = ("code", "expr", "metered")

    def __init__(self, expr: str, code: Code, *, metered: bool) -> None:
        self.expr = expr
        self.code = code
        self.metered = metered
        """Whether it can iterate (calls, comprehensions, lambdas, ``*`` and ``**``): only
        then is the evaluation's step budget kept."""


_ITERATING: Final = (
    ast.Call,
    ast.ListComp,
    ast.SetComp,
    ast.DictComp,
    ast.GeneratorExp,
    ast.Lambda,
    ast.Starred,
    ast.Dict,
)


# --- entry points --------------------------------------------------------------------------------

_cache: dict[str, Compiled] = {}


def compile_expr(expr: str) -> Compiled:
    """Parse and compile one expression (cached: the same text recurs in every macro call)."""
    hit = _cache.get(expr)
    if hit is not None:
        return hit
    source = expr.strip()
    lead = len(expr) - len(expr.lstrip())
    try:
        with warnings.catch_warnings():  # e.g. invalid escapes: Python's concern, not the user's
            warnings.simplefilter("ignore")
            tree = ast.parse(source, "<expression>", "eval")
    except SyntaxError as err:
        offset = None
        if err.offset and err.lineno == 1:
            offset = lead + err.offset - 1
        raise ExpressionError(
            expr, f"invalid expression '{expr}': {err.msg}", offset=offset
        ) from None
    except (RecursionError, MemoryError):
        # Python's parser stops at a fixed depth (a MemoryError for long unary chains).
        msg = f"the expression is nested too deeply to parse (more than {MAX_DEPTH} levels)"
        raise ExpressionError(expr, msg) from None
    try:
        code = Compiler(source, lead).compile(tree.body)
    except RefusedError as r:
        raise ExpressionError(expr, r.message, offset=r.offset, hint=r.hint) from None
    metered = any(isinstance(n, _ITERATING) for n in ast.walk(tree))
    compiled = Compiled(expr, code, metered=metered)
    if len(_cache) < 200_000:
        _cache[expr] = compiled
    return compiled


def evaluate(expr: str | Compiled, scope: Lookup) -> Any:
    """Evaluate one expression in ``scope``; whatever it raises or is refused becomes an
    :class:`ExpressionError` naming the expression."""
    compiled = expr if type(expr) is Compiled else compile_expr(expr)  # type: ignore[arg-type]
    try:
        if compiled.metered:
            return _run_metered(compiled.code, scope)
        return compiled.code(scope)
    except RefusedError as r:
        raise ExpressionError(compiled.expr, r.message, offset=r.offset, hint=r.hint) from None
    except (BelvedereError, RecursionError):
        raise
    except Exception as err:  # noqa: BLE001 (user expressions may raise anything)
        raise ExpressionError.raised(compiled.expr, err) from None


def _run_metered(code: Code, scope: Lookup) -> Any:
    """Run with a fresh step budget, unless an evaluation that keeps one is already running
    (a lazy property evaluated inside it shares its budget)."""
    state = budget
    if state.depth == 0:
        state.steps = 0
    state.depth += 1
    try:
        return code(scope)
    finally:
        state.depth -= 1
