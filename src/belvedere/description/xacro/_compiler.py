"""The compiler of the expression language: each node of Python's syntax tree that xacro
documents becomes a closure over the names it reads; anything else is refused, naming the
construct and its column (see :mod:`._interpreter`)."""

from __future__ import annotations

import ast
from collections.abc import Callable, Iterator
from typing import Any, Final

from belvedere.description.xacro._bounds import (
    BINOPS,
    COMPARE,
    MAX_DEPTH,
    RefusedError,
    add,
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

__all__ = ["Compiler"]


class Compiler:
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
