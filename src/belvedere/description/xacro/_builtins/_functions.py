"""The functions expressions may call: xacro's builtins and :mod:`math`, bounded, and the
one check every call goes through."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from typing import Any, Final

from belvedere.description.xacro._bounds import (
    CONTAINERS,
    MAX_INT_BITS,
    MAX_ITEMS,
    RefusedError,
    add,
    check_container,
    check_int,
    metered,
    mul,
    per_item,
    refuse,
)
from belvedere.description.xacro._builtins._values import Lambda, YamlDict, _Bound, _Exposed

__all__ = ["call", "math_functions", "python_functions"]


def _guarded(function: Any) -> Callable[..., Any] | None:
    """What a builtin may call on our behalf (``map``'s function, ``sorted``'s key): only what
    an expression could call itself."""
    if function is None:
        return None

    def guarded_call(*args: Any) -> Any:
        return call(function, args, {}, None)

    return guarded_call


def _consumer(function: Callable[..., Any], name: str) -> Callable[..., Any]:
    """A builtin that iterates its first argument, charged for it; container results checked."""

    def call(*args: Any, **kwargs: Any) -> Any:
        if args:
            args = (metered(args[0]), *args[1:])
        if "key" in kwargs:
            kwargs["key"] = _guarded(kwargs["key"])
        result = function(*args, **kwargs)
        if isinstance(result, CONTAINERS):
            check_container(result)
        return result

    call.__name__ = call.__qualname__ = name
    return call


def _min_max(function: Callable[..., Any], name: str) -> Callable[..., Any]:
    def call(*args: Any, **kwargs: Any) -> Any:
        if "key" in kwargs:
            kwargs["key"] = _guarded(kwargs["key"])
        if len(args) == 1:
            return function(metered(args[0]), **kwargs)
        return function(*args, **kwargs)

    call.__name__ = call.__qualname__ = name
    return call


def _range(*args: int) -> range:
    r = range(*args)
    if len(r) > MAX_ITEMS:
        refuse(f"a range of {len(r):,} items is too large (at most {MAX_ITEMS:,})", hint=None)
    return r


def _int(value: Any = 0, *base: int) -> int:
    # Python caps digit strings at 4300 digits, but PYTHONINTMAXSTRDIGITS=0 lifts the cap and
    # the conversion is quadratic: the bound is ours.
    if isinstance(value, str | bytes) and len(value) > 5000:
        refuse(f"int() of a {len(value):,}-character string is too large", hint=None)
    return int(value, *base)


def _sum(items: Iterable[Any], start: Any = 0) -> Any:
    if not isinstance(start, int | float | complex):
        refuse("sum() adds numbers only (its start value is not a number)", hint=None)
    total = start
    for item in metered(items):
        total = add(total, item, None)
    return total


def _lazy(function: Callable[..., Any], name: str) -> Callable[..., Any]:
    """map/filter/zip/enumerate/reversed: iterables charged per item when consumed."""

    def call(*args: Any, **kwargs: Any) -> Any:
        if name in ("map", "filter") and args:
            first = args[0] if args[0] is None else _guarded(args[0])
            args = (first, *(metered(a) for a in args[1:]))
        elif name == "zip":
            args = tuple(metered(a) for a in args)
        elif args:  # enumerate(iterable, start), reversed(sequence)
            args = (metered(args[0]), *args[1:]) if name == "enumerate" else args
        return per_item(function(*args, **kwargs))

    call.__name__ = call.__qualname__ = name
    return call


_CONSTRUCTORS: Final = ("list", "tuple", "set", "frozenset", "dict", "sorted", "all", "any")


def _make_python_functions() -> dict[str, Any]:
    table: dict[str, Any] = {
        "len": len,
        "str": str,
        "float": float,
        "int": _int,
        "bool": bool,
        "True": True,
        "False": False,
        "round": round,
        "abs": abs,
        "complex": complex,
        "divmod": divmod,
        "hash": hash,
        "isinstance": isinstance,
        "issubclass": issubclass,
        "ord": ord,
        "repr": repr,
        "slice": slice,
        "range": _range,
        "sum": _sum,
        "min": _min_max(min, "min"),
        "max": _min_max(max, "max"),
    }
    for name in _CONSTRUCTORS:
        table[name] = _consumer(_BUILTINS[name], name)
    for name in ("map", "filter", "zip", "enumerate", "reversed"):
        table[name] = _lazy(_BUILTINS[name], name)
    return table


_BUILTINS: Final[dict[str, Any]] = {
    "list": list,
    "tuple": tuple,
    "set": set,
    "frozenset": frozenset,
    "dict": dict,
    "sorted": sorted,
    "all": all,
    "any": any,
    "map": map,
    "filter": filter,
    "zip": zip,
    "enumerate": enumerate,
    "reversed": reversed,
}


def _int_result_bits(log2_value: float, what: str) -> None:
    if log2_value > MAX_INT_BITS:
        refuse(f"{what} is too large (more than {MAX_INT_BITS:,} bits)", hint=None)


def _lg(n: float) -> float:
    return math.lgamma(n + 1) / math.log(2)


def _factorial(n: int) -> int:
    if isinstance(n, int) and n > 0:
        _int_result_bits(_lg(n), f"factorial({n})")
    return math.factorial(n)


def _comb(n: int, k: int) -> int:
    if isinstance(n, int) and isinstance(k, int) and 0 <= k <= n:
        _int_result_bits(_lg(n) - _lg(k) - _lg(n - k), f"comb({n}, {k})")
    return math.comb(n, k)


def _perm(n: int, k: int | None = None) -> int:
    if isinstance(n, int) and n >= 0 and (k is None or (isinstance(k, int) and 0 <= k <= n)):
        _int_result_bits(_lg(n) - _lg(n - (n if k is None else k)), f"perm({n}, {k})")
    return math.perm(n, k)


def _prod(items: Iterable[Any], *, start: Any = 1) -> Any:
    total = start
    for item in metered(items):
        total = mul(total, item, None)
    return total


def _lcm(*values: int) -> int:
    total = 1
    for v in values:
        total = check_int(math.lcm(total, v), None)
    return total


def _make_math_functions() -> dict[str, Any]:
    table = {k: v for k, v in vars(math).items() if not k.startswith("_")}
    table.update(factorial=_factorial, comb=_comb, perm=_perm, prod=_prod, lcm=_lcm)
    for name in ("fsum", "sumprod"):
        if name in table:
            table[name] = _consumer(table[name], name)
    return table


_PYTHON: Final = _make_python_functions()
_MATH: Final = _make_math_functions()


def python_functions() -> dict[str, Any]:
    """The builtins xacro exposes (as ``python.*``; thirteen of them also bare), bounded.

    ``type`` and ``vars`` are left out: they lead to every class and module of the process."""
    return dict(_PYTHON)


def math_functions() -> dict[str, Any]:
    """Every public name of :mod:`math`; the few that can build huge integers are bounded."""
    return dict(_MATH)


_ALLOWED_IDS: Final = frozenset(
    id(v) for v in (*_PYTHON.values(), *_MATH.values(), YamlDict) if callable(v)
)
_CALLABLE_TYPES: Final = (Lambda, _Bound, _Exposed)


def call(function: Any, args: tuple[Any, ...], kwargs: dict[str, Any], offset: int | None) -> Any:
    if id(function) in _ALLOWED_IDS or isinstance(function, _CALLABLE_TYPES):
        try:
            return function(*args, **kwargs)
        except RefusedError as r:
            if r.offset is None:  # refused inside the function: point at the call
                r.offset = offset
            raise
    if not callable(function):
        msg = f"'{type(function).__name__}' object is not callable"
        raise TypeError(msg)
    msg = f"calling {function!r} is not allowed in expressions"
    raise RefusedError(msg, offset)
