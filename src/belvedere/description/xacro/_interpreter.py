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
from collections.abc import Callable, Iterator
from typing import Any, Final, Protocol

from belvedere.description.xacro._bounds import (
    BINOPS,
    COMPARE,
    MAX_DEPTH,
    RefusedError,
    add,
    budget,
    check_container,
    check_spec,
    check_str,
    metered,
    mul,
    refuse,
    sub,
    truediv,
)
from belvedere.description.xacro._builtins import (
    MISSING,
    NO_KWARGS,
    Code,
    Frame,
    Lambda,
    attribute,
    call,
)
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


# --- the compiler --------------------------------------------------------------------------------


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


class _Compiler:
    def __init__(self, source: str, lead: int) -> None:
        self.source = source
        self.lead = lead
        """Characters stripped before the source (offsets are into the original text)."""
        self.depth = 0
        self._utf8 = source.encode() if not source.isascii() else None

    def offset(self, node: ast.AST) -> int:
        col: int = getattr(node, "col_offset", 0)
        if self._utf8 is not None:
            col = len(self._utf8[:col].decode(errors="replace"))
        return self.lead + col

    def _dot(self, node: ast.Attribute) -> int:
        """Where the ``.name`` of an attribute starts (after any parentheses of its value)."""
        end = self.offset(node.value) + len(ast.get_source_segment(self.source, node.value) or "")
        dot = self.source.find(".", end - self.lead)
        return self.lead + dot if dot >= 0 else self.offset(node)

    def compile(self, node: ast.AST) -> Code:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            refuse(
                f"the expression is nested more than {MAX_DEPTH} levels deep",
                self.offset(node),
                None,
            )
        try:
            handler = getattr(self, "c_" + type(node).__name__.lower(), None)
            if handler is None:
                refuse(f"{_describe(node)} is not allowed in expressions", self.offset(node))
            code: Code = handler(node)
            return code
        finally:
            self.depth -= 1

    # leaves
    def c_constant(self, node: ast.Constant) -> Code:
        value = node.value
        return lambda s: value

    def c_name(self, node: ast.Name) -> Code:
        name = node.id
        if name.startswith("__"):
            refuse(
                f"the name '{name}' is not allowed (names starting with '__')", self.offset(node)
            )

        def get(s: Any) -> Any:
            try:
                return s[name]
            except KeyError:
                msg = f"name '{name}' is not defined"
                raise NameError(msg, name=name) from None

        return get

    # operators
    def c_binop(self, node: ast.BinOp) -> Code:
        # a + b + c + … is a left-leaning chain: compile it flat, so long sums need no depth
        chain: list[tuple[Callable[[Any, Any, int | None], Any], ast.AST, int]] = []
        left: ast.AST = node
        while isinstance(left, ast.BinOp):
            chain.append((BINOPS[type(left.op)], left.right, self.offset(left)))
            left = left.left
        chain.reverse()
        first = self.compile(left)
        steps = tuple((op, self.compile(right), off) for op, right, off in chain)
        if len(steps) == 1:
            ((op, right, off),) = steps
            if op is add:
                return _fast_add(first, right, off)
            if op is sub:
                return lambda s: first(s) - right(s)
            if op is mul:
                return _fast_mul(first, right, off)
            if op is truediv:
                return lambda s: first(s) / right(s)
            return lambda s: op(first(s), right(s), off)

        def run(s: Any) -> Any:
            value = first(s)
            for op, right, off in steps:
                value = op(value, right(s), off)
            return value

        return run

    def c_unaryop(self, node: ast.UnaryOp) -> Code:
        operand = self.compile(node.operand)
        op = type(node.op)
        if op is ast.USub:
            return lambda s: -operand(s)
        if op is ast.UAdd:
            return lambda s: +operand(s)
        if op is ast.Not:
            return lambda s: not operand(s)
        return lambda s: ~operand(s)

    def c_boolop(self, node: ast.BoolOp) -> Code:
        values = tuple(self.compile(v) for v in node.values)
        if isinstance(node.op, ast.And):

            def all_of(s: Any) -> Any:
                value: Any = True
                for v in values:
                    value = v(s)
                    if not value:
                        return value
                return value

            return all_of

        def any_of(s: Any) -> Any:
            value: Any = False
            for v in values:
                value = v(s)
                if value:
                    return value
            return value

        return any_of

    def c_compare(self, node: ast.Compare) -> Code:
        left = self.compile(node.left)
        ops = tuple(COMPARE[type(op)] for op in node.ops)
        rights = tuple(self.compile(c) for c in node.comparators)
        if len(ops) == 1:
            op, right = ops[0], rights[0]
            return lambda s: op(left(s), right(s))

        def chain(s: Any) -> Any:
            a = left(s)
            result: Any = True
            for op, right in zip(ops, rights, strict=True):
                b = right(s)
                result = op(a, b)
                if not result:
                    return result
                a = b
            return result

        return chain

    def c_ifexp(self, node: ast.IfExp) -> Code:
        test, body, orelse = (self.compile(n) for n in (node.test, node.body, node.orelse))
        return lambda s: body(s) if test(s) else orelse(s)

    # attribute, index, call
    def c_attribute(self, node: ast.Attribute) -> Code:
        name = node.attr
        off = self._dot(node)
        if name.startswith("_"):
            refuse(f"the attribute '{name}' is not allowed (names starting with '_')", off)
        value = self.compile(node.value)
        return lambda s: attribute(value(s), name, off)

    def c_subscript(self, node: ast.Subscript) -> Code:
        value = self.compile(node.value)
        index = self.compile(node.slice)
        return lambda s: value(s)[index(s)]

    def c_slice(self, node: ast.Slice) -> Code:
        parts = tuple(
            self.compile(p) if p is not None else None for p in (node.lower, node.upper, node.step)
        )
        lower, upper, step = parts
        return lambda s: slice(
            lower(s) if lower else None, upper(s) if upper else None, step(s) if step else None
        )

    def c_call(self, node: ast.Call) -> Code:
        off = self.offset(node)
        args = self._items(node.args)
        kw_names: tuple[str | None, ...] = tuple(k.arg for k in node.keywords)
        kw_values = tuple(self.compile(k.value) for k in node.keywords)
        func = node.func
        if isinstance(func, ast.Attribute):
            # obj.method(…): look the method up without making a bound wrapper
            name = func.attr
            if name.startswith("_"):
                refuse(
                    f"the attribute '{name}' is not allowed (names starting with '_')",
                    self.offset(func),
                )
            target = self.compile(func.value)

            attr_off = self.offset(func) + len(
                ast.get_source_segment(self.source, func.value) or ""
            )

            def method(s: Any) -> Any:
                return attribute(target(s), name, attr_off)

            function: Code = method
        else:
            function = self.compile(func)
        simple = not kw_names and all(type(a) is not _Star for a in args)
        if simple and len(args) == 1:
            (one,) = args
            return lambda s: call(function(s), (one(s),), NO_KWARGS, off)
        if simple and len(args) == 2:
            a, b = args
            return lambda s: call(function(s), (a(s), b(s)), NO_KWARGS, off)
        spread = self._spread

        def run_call(s: Any) -> Any:
            f = function(s)
            kwargs: dict[str, Any] = {}
            for k, v in zip(kw_names, kw_values, strict=True):
                if k is None:
                    kwargs.update(v(s))
                else:
                    kwargs[k] = v(s)
            return call(f, tuple(spread(args, s)), kwargs, off)

        return run_call

    def _items(self, nodes: list[ast.expr]) -> tuple[Code, ...]:
        """Compiled items of a display or call; a ``*x`` item is a :class:`_Star`."""
        out: list[Code] = []
        for n in nodes:
            if isinstance(n, ast.Starred):
                inner = self.compile(n.value)
                out.append(_Star(inner))
            else:
                out.append(self.compile(n))
        return tuple(out)

    @staticmethod
    def _spread(items: tuple[Code, ...], s: Any) -> Iterator[Any]:
        for item in items:
            if type(item) is _Star:
                yield from metered(item.code(s))
            else:
                yield item(s)

    # displays
    def c_list(self, node: ast.List) -> Code:
        items = self._items(node.elts)
        spread = self._spread
        return lambda s: check_container([*spread(items, s)])

    def c_tuple(self, node: ast.Tuple) -> Code:
        items = self._items(node.elts)
        if all(type(i) is not _Star for i in items):
            if len(items) == 2:
                a, b = items
                return lambda s: check_container((a(s), b(s)))
            return lambda s: check_container(tuple(i(s) for i in items))
        spread = self._spread
        return lambda s: check_container(tuple(spread(items, s)))

    def c_set(self, node: ast.Set) -> Code:
        items = self._items(node.elts)
        spread = self._spread
        return lambda s: check_container(set(spread(items, s)))

    def c_dict(self, node: ast.Dict) -> Code:
        pairs = tuple(
            (self.compile(k) if k is not None else None, self.compile(v))
            for k, v in zip(node.keys, node.values, strict=True)
        )

        def build(s: Any) -> Any:
            out: dict[Any, Any] = {}
            for k, v in pairs:
                if k is None:
                    out.update(metered(v(s)))
                else:
                    out[k(s)] = v(s)
            return check_container(out)

        return build

    def c_joinedstr(self, node: ast.JoinedStr) -> Code:
        parts = tuple(self.compile(v) for v in node.values)

        def join(s: Any) -> str:
            text = "".join([p(s) for p in parts])
            check_str(text)
            return text

        return join

    def c_formattedvalue(self, node: ast.FormattedValue) -> Code:
        value = self.compile(node.value)
        spec = self.compile(node.format_spec) if node.format_spec is not None else None
        convert = {-1: None, 115: str, 114: repr, 97: ascii}[node.conversion]
        off = self.offset(node)

        def formatted(s: Any) -> str:
            v = value(s)
            if convert is not None:
                v = convert(v)
            text = spec(s) if spec is not None else ""
            check_spec(text, off)
            return format(v, text)

        return formatted

    # functions and comprehensions
    def c_lambda(self, node: ast.Lambda) -> Code:
        a = node.args
        if a.posonlyargs or a.kwarg:
            refuse("lambdas with positional-only or ** parameters", self.offset(node))
        params = tuple(p.arg for p in a.args)
        for p in (*a.args, *a.kwonlyargs, *([a.vararg] if a.vararg else [])):
            if p.arg.startswith("__"):
                refuse(f"the name '{p.arg}' is not allowed (names starting with '__')")
        defaults = tuple(self.compile(d) for d in a.defaults)
        kw_defaults = tuple(self.compile(d) if d is not None else None for d in a.kw_defaults)
        kwonly = tuple(p.arg for p in a.kwonlyargs)
        vararg = a.vararg.arg if a.vararg else None
        body = self.compile(node.body)

        def make(s: Any) -> Lambda:
            kw = tuple(
                (n, d(s) if d is not None else MISSING)
                for n, d in zip(kwonly, kw_defaults, strict=True)
            )
            return Lambda(params, tuple(d(s) for d in defaults), vararg, kw, body, s)

        return make

    def _generators(
        self, generators: list[ast.comprehension]
    ) -> tuple[tuple[Callable[[dict[str, Any], Any], None], Code, tuple[Code, ...]], ...]:
        out = []
        for g in generators:
            if g.is_async:
                refuse("async comprehensions", self.offset(g.target))
            out.append(
                (
                    self._target(g.target),
                    self.compile(g.iter),
                    tuple(self.compile(c) for c in g.ifs),
                )
            )
        return tuple(out)

    def _target(self, node: ast.expr) -> Callable[[dict[str, Any], Any], None]:
        if isinstance(node, ast.Name):
            name = node.id
            if name.startswith("__"):
                refuse(f"the name '{name}' is not allowed (names starting with '__')")

            def bind(names: dict[str, Any], value: Any) -> None:
                names[name] = value

            return bind
        if isinstance(node, ast.Tuple | ast.List) and not any(
            isinstance(e, ast.Starred) for e in node.elts
        ):
            parts = tuple(self._target(e) for e in node.elts)

            def unpack(names: dict[str, Any], value: Any) -> None:
                values = tuple(value)
                if len(values) != len(parts):
                    msg = f"cannot unpack {len(values)} values into {len(parts)} names"
                    raise ValueError(msg)
                for p, v in zip(parts, values, strict=True):
                    p(names, v)

            return unpack
        msg = f"{_describe(node)} as a loop variable is not allowed in expressions"
        raise RefusedError(msg, self.offset(node))

    def _comprehension(self, generators: list[ast.comprehension], emit: Code) -> Code:
        """A code whose value iterates the comprehension, yielding ``emit`` for each item."""
        gens = self._generators(generators)
        last = len(gens) - 1

        def run(s: Any) -> Iterator[Any]:
            frame = Frame({}, s)

            def loop(level: int) -> Iterator[Any]:
                bind, source, ifs = gens[level]
                for item in metered(source(s if level == 0 else frame)):
                    bind(frame.vars, item)
                    if all(c(frame) for c in ifs):
                        if level == last:
                            yield emit(frame)
                        else:
                            yield from loop(level + 1)

            return loop(0)

        return run

    def c_listcomp(self, node: ast.ListComp) -> Code:
        run = self._comprehension(node.generators, self.compile(node.elt))
        return lambda s: check_container(list(run(s)))

    def c_setcomp(self, node: ast.SetComp) -> Code:
        run = self._comprehension(node.generators, self.compile(node.elt))
        return lambda s: check_container(set(run(s)))

    def c_generatorexp(self, node: ast.GeneratorExp) -> Code:
        return self._comprehension(node.generators, self.compile(node.elt))

    def c_dictcomp(self, node: ast.DictComp) -> Code:
        key, value = self.compile(node.key), self.compile(node.value)
        run = self._comprehension(node.generators, lambda f: (key(f), value(f)))
        return lambda s: check_container(dict(run(s)))


class _Star:
    """A ``*x`` item of a display or call."""

    __slots__ = ("code",)

    def __init__(self, code: Code) -> None:
        self.code = code

    def __call__(self, s: Any) -> Any:  # pragma: no cover - never called directly
        return self.code(s)


def _fast_add(first: Code, right: Code, off: int) -> Code:
    def fast_add(s: Any) -> Any:
        a = first(s)
        b = right(s)
        if type(a) is float or type(b) is float:
            return a + b
        return add(a, b, off)

    return fast_add


def _fast_mul(first: Code, right: Code, off: int) -> Code:
    def fast_mul(s: Any) -> Any:
        a = first(s)
        b = right(s)
        if type(a) is float or type(b) is float:
            return a * b
        return mul(a, b, off)

    return fast_mul


_DESCRIPTIONS: Final[dict[str, str]] = {
    "NamedExpr": "the assignment expression ':='",
    "Await": "'await'",
    "Yield": "'yield'",
    "YieldFrom": "'yield from'",
    "Starred": "'*' unpacking here",
}


def _describe(node: ast.AST) -> str:
    name = type(node).__name__
    return _DESCRIPTIONS.get(name, f"the construct {name!r}")


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
        code = _Compiler(source, lead).compile(tree.body)
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
