"""The limits of the expression sandbox and the operations that respect them.

Every operation that can build a large value checks the size of what it will build before
building it (an exponent, a repetition, a shift, a format width), so no single step can run
for long or exhaust memory; iteration inside builtins and comprehensions is charged to a
per-evaluation budget.
"""

from __future__ import annotations

import ast
import math
import re
import threading
from collections.abc import Callable, Iterable, Iterator
from typing import Any, Final, NoReturn

__all__ = [
    "BINOPS",
    "COMPARE",
    "CONTAINERS",
    "HINT",
    "MAX_CALLS",
    "MAX_CHARS",
    "MAX_DEPTH",
    "MAX_FORMAT_WIDTH",
    "MAX_INT_BITS",
    "MAX_ITEMS",
    "MAX_STEPS",
    "MAX_WEIGHT",
    "RefusedError",
    "add",
    "budget",
    "charge",
    "check_container",
    "check_int",
    "check_spec",
    "check_str",
    "check_weight",
    "metered",
    "mul",
    "per_item",
    "refuse",
    "sub",
    "truediv",
]

MAX_DEPTH: Final = 100
"""Nesting of the syntax tree (parentheses, calls, unary operators; long ``a+b+c…`` chains
are flat and do not count)."""
MAX_INT_BITS: Final = 1 << 15
"""Largest integer result, in bits (32768 bits ≈ 9900 digits; Python prints at most 4300)."""
MAX_CHARS: Final = 10_000_000
"""Longest string an expression may build."""
MAX_ITEMS: Final = 1_000_000
"""Longest list, tuple or range an expression may build."""
MAX_WEIGHT: Final = 10_000_000
"""Most elements a nested value may hold, shared parts counted each time they appear."""
MAX_STEPS: Final = 10_000_000
"""Most items iterated (by builtins and comprehensions) and lambda calls per evaluation."""
MAX_CALLS: Final = 100
"""Deepest nesting of lambda calls."""
MAX_FORMAT_WIDTH: Final = 10_000
"""Largest width or precision in a format specification."""

HINT: Final = (
    "expressions may use numbers, strings, lists, tuples, dicts, arithmetic, comparisons, "
    "conditions, indexing, comprehensions, lambdas, the listed builtins (python.*), math.*, "
    "xacro.*, YAML data (cfg.a.b) and string methods"
)


class RefusedError(Exception):
    """A construct or a size the sandbox refuses, raised while compiling or evaluating; the
    interpreter turns it into an ExpressionError naming the expression."""

    def __init__(self, message: str, offset: int | None = None, hint: str | None = HINT) -> None:
        super().__init__(message)
        self.message = message
        self.offset = offset
        self.hint = hint


def refuse(message: str, offset: int | None = None, hint: str | None = HINT) -> NoReturn:
    raise RefusedError(message, offset, hint)


# --- budgets -------------------------------------------------------------------------------------


class _Budget(threading.local):
    """Steps and lambda depth of the evaluation running on this thread (nested evaluations,
    e.g. of lazy properties, share the outermost one's budget)."""

    def __init__(self) -> None:
        self.steps = 0
        self.calls = 0
        self.depth = 0


budget: Final = _Budget()


def charge(n: int) -> None:
    budget.steps += n
    if budget.steps > MAX_STEPS:
        refuse(f"the expression does too much work (more than {MAX_STEPS:,} steps)")


_SIZED: Final = (str, bytes, list, tuple, dict, set, frozenset, range)


def metered(items: Any) -> Any:
    """``items`` with its iteration charged: at once when its size is known, else per item."""
    if isinstance(items, _SIZED):
        charge(len(items))
        return items
    return per_item(items)


def per_item(items: Iterable[Any]) -> Iterator[Any]:
    for item in items:
        charge(1)
        yield item


# --- sizes ---------------------------------------------------------------------------------------

_SCALARS: Final = frozenset({int, float, bool, complex, type(None), str, bytes})
CONTAINERS: Final = (list, tuple, dict, set, frozenset)


def _weight(value: Any, memo: dict[int, int], active: set[int]) -> int:
    t = type(value)
    if t is str or t is bytes:
        return 1 + len(value) // 8
    if t in _SCALARS or not isinstance(value, CONTAINERS):
        return 1
    key = id(value)
    known = memo.get(key)
    if known is not None:
        return known
    if key in active:
        refuse("a value that contains itself cannot be used in expressions")
    active.add(key)
    total = 1
    parts: Iterable[Any] = (*value.keys(), *value.values()) if isinstance(value, dict) else value
    for item in parts:
        total += _weight(item, memo, active)
        if total > MAX_WEIGHT:
            break
    active.discard(key)
    memo[key] = total
    return total


def check_weight(value: Any, what: str = "the value") -> Any:
    """Refuse a nested value that would hold more than :data:`MAX_WEIGHT` elements when
    expanded (shared parts counted where they appear); return it otherwise."""
    if type(value) in _SCALARS:
        return value
    if _weight(value, {}, set()) > MAX_WEIGHT:
        refuse(
            f"{what} is too large: more than {MAX_WEIGHT:,} elements when its shared parts "
            "are expanded",
            hint=None,
        )
    return value


def check_container(value: Any, offset: int | None = None) -> Any:
    n = len(value)
    if n > MAX_ITEMS:
        refuse(f"a {type(value).__name__} of {n:,} items is too large (at most {MAX_ITEMS:,})")
    for item in value.values() if isinstance(value, dict) else value:
        if type(item) not in _SCALARS:
            return check_weight(value, f"the {type(value).__name__}")
    return value


def check_int(value: int, offset: int | None) -> int:
    if value.bit_length() > MAX_INT_BITS:
        refuse(f"an integer of {value.bit_length():,} bits is too large", offset, None)
    return value


def check_str(value: Any, offset: int | None = None) -> Any:
    if len(value) > MAX_CHARS:
        refuse(f"a string of {len(value):,} characters is too large", offset, None)
    return value


def _bits(value: int) -> float:
    return math.log2(abs(value)) if value else 0.0


# --- arithmetic with bounds -----------------------------------------------------------------------


def add(a: Any, b: Any, offset: int | None) -> Any:
    r = a + b
    t = type(r)
    if t is float or t is int or (t is str and len(r) <= MAX_CHARS):
        return r
    if t is str or t is bytes:
        return check_str(r, offset)
    if t is list or t is tuple:
        return check_container(r, offset)
    return r


def _repeat_check(seq: Any, n: Any, offset: int | None) -> None:
    if not isinstance(n, int) or n <= 0:
        return
    size = len(seq) * n
    if isinstance(seq, str | bytes):
        if size > MAX_CHARS:
            refuse(f"repeating a string {n:,} times gives {size:,} characters", offset, None)
    elif size > MAX_ITEMS:
        refuse(f"repeating a sequence {n:,} times gives {size:,} items", offset, None)
    elif any(type(item) not in _SCALARS for item in seq):
        one = _weight(seq, {}, set())
        if one * n > MAX_WEIGHT:
            refuse(
                f"repeating a nested sequence {n:,} times gives more than {MAX_WEIGHT:,} elements",
                offset,
                None,
            )


def mul(a: Any, b: Any, offset: int | None) -> Any:
    ta, tb = type(a), type(b)
    if ta is float or tb is float:
        return a * b
    if isinstance(a, int) and isinstance(b, int):
        if a.bit_length() + b.bit_length() > MAX_INT_BITS + 1:
            refuse(f"the product is too large (more than {MAX_INT_BITS:,} bits)", offset, None)
        return a * b
    if isinstance(a, str | bytes | list | tuple):
        _repeat_check(a, b, offset)
    elif isinstance(b, str | bytes | list | tuple):
        _repeat_check(b, a, offset)
    return a * b


def _pow(a: Any, b: Any, offset: int | None) -> Any:
    if isinstance(a, int) and isinstance(b, int) and b > 0 and _bits(a) * b > MAX_INT_BITS:
        refuse(
            f"{a if a.bit_length() < 64 else 'a large number'} ** {b} is too large "
            f"(more than {MAX_INT_BITS:,} bits)",
            offset,
            None,
        )
    return a**b


def _lshift(a: Any, b: Any, offset: int | None) -> Any:
    if isinstance(a, int) and isinstance(b, int) and a and b > MAX_INT_BITS - a.bit_length():
        refuse(f"shifting by {b} is too large (more than {MAX_INT_BITS:,} bits)", offset, None)
    return a << b


_PERCENT: Final = re.compile(r"%(?:\([^)]*\))?[#0 +\-]*(\*|\d+)?(?:\.(\*|\d+))?[hlL]?.")


def check_spec(spec: str, offset: int | None = None) -> None:
    """Refuse format specifications whose width or precision would build huge strings."""
    for digits in re.findall(r"\d+", spec):
        if len(digits) > 5 or int(digits) > MAX_FORMAT_WIDTH:
            refuse(f"a format width of {digits} is too large", offset, None)


def _mod(a: Any, b: Any, offset: int | None) -> Any:
    if isinstance(a, str | bytes):
        fmt = a if isinstance(a, str) else a.decode("latin-1")
        for m in _PERCENT.finditer(fmt):
            if "*" in m.group(0):
                refuse("'*' widths in %-formatting are not allowed", offset, None)
            check_spec(m.group(0), offset)
        return check_str(a % b, offset)
    return a % b


def sub(a: Any, b: Any, offset: int | None) -> Any:
    return a - b


def truediv(a: Any, b: Any, offset: int | None) -> Any:
    return a / b


def _floordiv(a: Any, b: Any, offset: int | None) -> Any:
    return a // b


def _rshift(a: Any, b: Any, offset: int | None) -> Any:
    return a >> b


def _bitor(a: Any, b: Any, offset: int | None) -> Any:
    r = a | b
    return check_container(r, offset) if isinstance(r, dict | set | frozenset) else r


def _bitand(a: Any, b: Any, offset: int | None) -> Any:
    return a & b


def _bitxor(a: Any, b: Any, offset: int | None) -> Any:
    return a ^ b


def _matmul(a: Any, b: Any, offset: int | None) -> Any:
    return a @ b


BINOPS: Final[dict[type[ast.operator], Callable[[Any, Any, int | None], Any]]] = {
    ast.Add: add,
    ast.Sub: sub,
    ast.Mult: mul,
    ast.Div: truediv,
    ast.FloorDiv: _floordiv,
    ast.Mod: _mod,
    ast.Pow: _pow,
    ast.LShift: _lshift,
    ast.RShift: _rshift,
    ast.BitOr: _bitor,
    ast.BitAnd: _bitand,
    ast.BitXor: _bitxor,
    ast.MatMult: _matmul,
}

COMPARE: Final[dict[type[ast.cmpop], Callable[[Any, Any], Any]]] = {
    ast.Eq: lambda a, b: a == b,
    ast.NotEq: lambda a, b: a != b,
    ast.Lt: lambda a, b: a < b,
    ast.LtE: lambda a, b: a <= b,
    ast.Gt: lambda a, b: a > b,
    ast.GtE: lambda a, b: a >= b,
    ast.Is: lambda a, b: a is b,
    ast.IsNot: lambda a, b: a is not b,
    ast.In: lambda a, b: a in b,
    ast.NotIn: lambda a, b: a not in b,
}
