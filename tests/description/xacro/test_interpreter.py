"""The expression interpreter on its own: Python's semantics for what it allows (checked
against Python's eval on generated expressions), refusals for what it does not."""

from __future__ import annotations

import math
import warnings
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from belvedere.description.xacro._builtins import (
    YamlDict,
    expose,
    math_functions,
    python_functions,
)
from belvedere.description.xacro._interpreter import ExpressionError, compile_expr, evaluate


def names(**extra: Any) -> dict[str, Any]:
    table = python_functions()
    table["math"] = None  # (namespaces are tested through xacro)
    table.update({k: v for k, v in math_functions().items() if k in ("pi", "sqrt", "cos")})
    table.update(extra)
    return table


def run(expr: str, **extra: Any) -> Any:
    return evaluate(expr, names(**extra))


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("{k: v * 2 for k, v in [('a', 1), ('b', 2)] if v > 1}", {"b": 4}),
        ("{x % 3 for x in range(10)}", {0, 1, 2}),
        ("{**{'a': 1}, 'b': 2}", {"a": 1, "b": 2}),
        ("dict(a=1, **{'b': 2})", {"a": 1, "b": 2}),
        ("f'{pi:.3f}-{name!r:>6}'", "3.142-   'w'"),
        ("'{0}-{name}-{1}'.format(1, 2, name='n')", "1-n-2"),
        ("'{a}'.format_map({'a': 5})", "5"),
        ("[(i, j) for i in range(2) for j in range(i)]", [(1, 0)]),
        ("(lambda *a, k=1: (a, k))(1, 2, k=3)", ((1, 2), 3)),
        ("(lambda x: (lambda y: x + y))(1)(2)", 3),
        ("[y for x in [[1, 2], [3]] for y in x]", [1, 2, 3]),
        ("sorted({'b': 1, 'a': 2}.items())", [("a", 2), ("b", 1)]),
        ("max([3, 1, 2], key=lambda v: -v)", 1),
        ("list(zip('ab', range(2)))", [("a", 0), ("b", 1)]),
        ("list(enumerate('ab', 1))", [(1, "a"), (2, "b")]),
        ("list(filter(None, [0, 1, '', 'x']))", [1, "x"]),
        ("list(reversed((1, 2)))", [2, 1]),
        ("(1, 2) < (1, 3) <= (2,)", True),
        ("1 if [] else 2 if {} else 3", 3),
        ("[1, 2, 3][::-1][1:]", [2, 1]),
        ("cfg.arm.length * 2", 0.5),
        ("cfg['arm'].get('n', 7)", 7),
        ("sqrt(16) + cos(0)", 5.0),
        ("len(set('aab')) + sum([1, 2])", 5),
        ("-2 ** 2", -4),
        ("not (1 and 0) or 0", True),
    ],
)
def test_constructs(expr: str, expected: Any) -> None:
    cfg = YamlDict({"arm": YamlDict({"length": 0.25})})
    assert run(expr, name="w", cfg=cfg) == expected


def test_host_functions_are_called_only_when_exposed() -> None:
    assert run("f(2)", f=expose(lambda x: x * 10, "f")) == 20
    with pytest.raises(ExpressionError, match=r"calling <built-in function print> is not allowed"):
        run("f('x')", f=print)
    with pytest.raises(ExpressionError, match=r"calling .* is not allowed"):
        run("f()", f=lambda: 1)  # a Python lambda given by the host, not exposed


def test_refusals_point_into_the_expression() -> None:
    with pytest.raises(ExpressionError) as info:
        evaluate("  1 + x.__class__", {"x": 1})
    assert info.value.offset == 7
    assert "    1 + x.__class__\n         ^" in info.value.message


def test_a_compiled_expression_is_reused() -> None:
    assert compile_expr("1 + 2 * x") is compile_expr("1 + 2 * x")
    assert evaluate(compile_expr("1 + 2 * x"), {"x": 3}) == 7


def test_nested_evaluations_share_one_budget() -> None:
    # A host function that evaluates another expression (a lazy property) charges the
    # outer evaluation's budget: the steps do not restart.
    inner = expose(lambda: evaluate("sum(range(6 * 10**5))", names()), "inner")
    with pytest.raises(ExpressionError, match="too much work"):
        run("[inner() for _ in range(20)]", inner=inner)


# --- Python's semantics, on generated expressions -------------------------------------------------

_LEAVES = st.sampled_from(["0", "1", "2", "-3", "0.5", "2.5", "x", "y", "'ab'", "True", "None"])


def _expressions() -> st.SearchStrategy[str]:
    def extend(inner: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
        binop = st.tuples(
            inner, st.sampled_from(["+", "-", "*", "/", "//", "%", "**", "<", "==", "in"]), inner
        ).map(lambda t: f"({t[0]} {t[1]} {t[2]})")
        boolop = st.tuples(inner, st.sampled_from(["and", "or"]), inner).map(
            lambda t: f"({t[0]} {t[1]} {t[2]})"
        )
        unary = st.tuples(st.sampled_from(["-", "not ", "+"]), inner).map(
            lambda t: f"({t[0]}{t[1]})"
        )
        ifexp = st.tuples(inner, inner, inner).map(lambda t: f"({t[0]} if {t[1]} else {t[2]})")
        display = st.lists(inner, max_size=3).map(lambda xs: f"[{', '.join(xs)}]")
        index = st.tuples(inner, inner).map(lambda t: f"{t[0]}[{t[1]}]")
        call = st.tuples(
            st.sampled_from(["abs", "len", "str", "int", "float", "bool", "min", "max", "round"]),
            st.lists(inner, min_size=1, max_size=2),
        ).map(lambda t: f"{t[0]}({', '.join(t[1])})")
        comp = st.tuples(inner, inner).map(lambda t: f"[v for v in {t[0]} if {t[1]}]")
        return binop | boolop | unary | ifexp | display | index | call | comp

    return st.recursive(_LEAVES, extend, max_leaves=12)


def _python(expr: str, scope: dict[str, Any]) -> tuple[str, Any]:
    # names as globals, so comprehensions see them (xacro's own eval hides its locals from
    # them, a quirk the old evaluator already smoothed over)
    table = {
        "abs": abs,
        "len": len,
        "str": str,
        "int": int,
        "float": float,
        "bool": bool,
        "min": min,
        "max": max,
        "round": round,
        **scope,
    }
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SyntaxWarning)
            return "ok", eval(expr, {"__builtins__": {}, **table})
    except Exception as err:  # noqa: BLE001 (compared with ours)
        return type(err).__name__, None


def _ours(expr: str, scope: dict[str, Any]) -> tuple[str, Any]:
    try:
        return "ok", evaluate(expr, names(**scope))
    except ExpressionError as err:
        return (type(err.cause).__name__ if err.cause else "refused"), None


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return bool(type(a) is type(b) and a == b)


@settings(max_examples=300, deadline=None)
@given(_expressions(), st.integers(-5, 5), st.sampled_from([0.0, 1.5, "s", [1, 2]]))
def test_same_results_as_python(expr: str, x: int, y: Any) -> None:
    scope = {"x": x, "y": y}
    theirs = _python(expr, scope)
    ours = _ours(expr, scope)
    if ours[0] == "refused":  # only sizes beyond our bounds may be refused
        assert "**" in expr or "*" in expr, expr
        return
    assert ours[0] == theirs[0], (expr, ours, theirs)
    if ours[0] == "ok":
        assert _same(ours[1], theirs[1]), (expr, ours, theirs)
