"""What expressions can reach: the values we make (YAML data, namespaces, lambdas, bound
methods), the functions they may call and the attributes they may read.

A value reaches Python's object model only through an attribute, a call or a format field;
all three are decided here, by type and by name, from explicit lists.
"""

from __future__ import annotations

import math
import re
import string
from collections.abc import Callable, Iterable, Mapping
from typing import Any, Final

from belvedere.description.xacro._bounds import (
    CONTAINERS,
    MAX_CALLS,
    MAX_CHARS,
    MAX_INT_BITS,
    MAX_ITEMS,
    RefusedError,
    add,
    budget,
    charge,
    check_container,
    check_int,
    check_spec,
    check_str,
    metered,
    mul,
    per_item,
    refuse,
)
from belvedere.description.xacro._errors import XacroError

Code = Callable[[Any], Any]
"""A compiled expression node: takes the names it reads from, returns its value."""

__all__ = [
    "MISSING",
    "NO_KWARGS",
    "Code",
    "Frame",
    "Lambda",
    "Namespace",
    "YamlDict",
    "YamlList",
    "attribute",
    "call",
    "expose",
    "math_functions",
    "python_functions",
    "to_yaml_value",
]

# --- values we made ----------------------------------------------------------------------------


class Namespace:
    """Marks a table of names reached with a dot (``math.pi``, ``xacro.load_yaml``, an
    include's ``ns.prop``): attribute access on it is item lookup."""

    __slots__ = ()

    def __getitem__(self, key: str, /) -> Any:
        raise KeyError(key)


class YamlDict(dict[Any, Any]):
    """A YAML mapping with dotted access: ``${cfg.arm.length}``."""

    __slots__ = ()

    def __getattr__(self, item: str) -> Any:
        try:
            return dict.__getitem__(self, item)
        except KeyError:
            msg = f"The yaml dictionary has no key '{item}'"
            raise AttributeError(msg) from None

    __getitem__ = __getattr__


class YamlList(list[Any]):
    """A YAML list (its mappings have dotted access)."""

    __slots__ = ()


def to_yaml_value(data: Any) -> Any:
    """Loaded YAML data with its mappings as :class:`YamlDict`, lists as :class:`YamlList`.

    Shared parts (YAML aliases) stay shared; a structure that contains itself is refused."""
    memo: dict[int, Any] = {}
    active: set[int] = set()

    def convert(item: Any) -> Any:
        if not isinstance(item, dict | list):
            return item
        key = id(item)
        if key in memo:
            return memo[key]
        if key in active:
            msg = "a YAML structure that contains itself (through an alias) is not supported"
            raise XacroError(msg)
        active.add(key)
        if isinstance(item, dict):
            out: Any = YamlDict({k: convert(v) for k, v in item.items()})
        else:
            out = YamlList(convert(v) for v in item)
        active.discard(key)
        memo[key] = out
        return out

    return convert(data)


class Lambda:
    """A lambda written in an expression: its variables live in our frames."""

    __slots__ = ("body", "defaults", "kwonly", "outer", "params", "vararg")

    def __init__(
        self,
        params: tuple[str, ...],
        defaults: tuple[Any, ...],
        vararg: str | None,
        kwonly: tuple[tuple[str, Any], ...],
        body: Code,
        outer: Any,
    ) -> None:
        self.params = params
        self.defaults = defaults
        self.vararg = vararg
        self.kwonly = kwonly
        self.body = body
        self.outer = outer

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        charge(1)
        names: dict[str, Any] = {}
        params = self.params
        n = len(params)
        if len(args) > n and self.vararg is None:
            msg = f"<lambda>() takes {n} positional arguments but {len(args)} were given"
            raise TypeError(msg)
        names.update(zip(params, args, strict=False))
        if self.vararg is not None:
            names[self.vararg] = tuple(args[n:])
        first_default = n - len(self.defaults)
        for i in range(len(args), n):
            name = params[i]
            if name in kwargs:
                names[name] = kwargs.pop(name)
            elif i >= first_default:
                names[name] = self.defaults[i - first_default]
            else:
                msg = f"<lambda>() missing required argument: '{name}'"
                raise TypeError(msg)
        for name, default in self.kwonly:
            names[name] = kwargs.pop(name, default)
            if names[name] is MISSING:
                msg = f"<lambda>() missing required keyword argument: '{name}'"
                raise TypeError(msg)
        if kwargs:
            msg = f"<lambda>() got an unexpected keyword argument '{next(iter(kwargs))}'"
            raise TypeError(msg)
        if budget.calls >= MAX_CALLS:
            refuse(f"lambdas calling each other deeper than {MAX_CALLS} levels")
        budget.calls += 1
        try:
            return self.body(Frame(names, self.outer))
        finally:
            budget.calls -= 1

    def __repr__(self) -> str:
        return "<lambda>"


class Frame:
    """The variables of a lambda call or a comprehension, in front of the enclosing names."""

    __slots__ = ("outer", "vars")

    def __init__(self, names: dict[str, Any], outer: Any) -> None:
        self.vars = names
        self.outer = outer

    def __getitem__(self, key: str) -> Any:
        value = self.vars.get(key, MISSING)
        if value is MISSING:
            return self.outer[key]
        return value


class _Bound:
    """A whitelisted method bound to its value (what ``'abc'.upper`` evaluates to)."""

    __slots__ = ("function", "value")

    def __init__(self, function: Callable[..., Any], value: Any) -> None:
        self.function = function
        self.value = value

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.function(self.value, *args, **kwargs)

    def __repr__(self) -> str:
        return f"<method of {type(self.value).__name__}>"


class _Exposed:
    """A function of the host (xacro's ``load_yaml``, launch's ``find``…) made callable."""

    __slots__ = ("function", "name")

    def __init__(self, function: Callable[..., Any], name: str) -> None:
        self.function = function
        self.name = name

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.function(*args, **kwargs)

    def __repr__(self) -> str:
        return f"<function {self.name}>"


def expose(function: Callable[..., Any], name: str | None = None) -> Callable[..., Any]:
    """Make a host function callable from expressions (calls of anything not exposed, not a
    listed builtin and not a lambda of the expression are refused)."""
    return _Exposed(function, name or str(getattr(function, "__name__", "function")))


MISSING: Final = object()
NO_KWARGS: Final[dict[str, Any]] = {}


# --- the functions expressions may call ----------------------------------------------------------


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


# --- methods -----------------------------------------------------------------------------------

_FORMATTER: Final = string.Formatter()


def _check_format_string(fmt: str, offset: int | None, depth: int = 0) -> None:
    try:
        fields = list(_FORMATTER.parse(fmt))
    except ValueError as err:
        refuse(f"invalid format string {fmt!r}: {err}", offset, None)
    for _, field, spec, _ in fields:
        if field is None:
            continue
        if field and not (field.isdigit() or field.isidentifier()):
            refuse(
                f"format field '{{{field}}}' is not allowed (only names and positions: "
                "'{0}', '{name}', '{}')",
                offset,
                None,
            )
        if spec:
            if depth > 1:
                refuse("format specifications nested too deeply", offset, None)
            _check_format_string(spec, offset, depth + 1)
            check_spec(re.sub(r"\{[^}]*\}", "", spec), offset)


def _format(value: str, *args: Any, **kwargs: Any) -> str:
    _check_format_string(value, None)
    result: str = check_str(value.format(*args, **kwargs))
    return result


def _format_map(value: str, mapping: Mapping[str, Any]) -> str:
    _check_format_string(value, None)
    result: str = check_str(value.format_map(mapping))
    return result


def _join(value: str, items: Iterable[Any]) -> str:
    parts = list(metered(items))
    size = sum(len(p) for p in parts if isinstance(p, str)) + len(value) * len(parts)
    if size > MAX_CHARS:
        refuse(f"joining gives {size:,} characters, more than {MAX_CHARS:,}", hint=None)
    return value.join(parts)


def _replace(value: str, old: str, new: str, count: int = -1) -> str:
    if isinstance(old, str) and isinstance(new, str) and len(new) > len(old):
        hits = value.count(old) if old else len(value) + 1
        if count >= 0:
            hits = min(hits, count)
        if len(value) + hits * (len(new) - len(old)) > MAX_CHARS:
            refuse(f"replace() would give more than {MAX_CHARS:,} characters", hint=None)
    return value.replace(old, new, count)


def _width(method: Callable[..., str]) -> Callable[..., str]:
    def call(value: str, width: int, *args: Any) -> str:
        if isinstance(width, int) and width > MAX_CHARS:
            refuse(f"a width of {width:,} is more than {MAX_CHARS:,} characters", hint=None)
        return method(value, width, *args)

    return call


def _expandtabs(value: str, tabsize: int = 8) -> str:
    if isinstance(tabsize, int) and tabsize > 0 and len(value) * tabsize > MAX_CHARS:
        refuse(f"expandtabs() could give more than {MAX_CHARS:,} characters", hint=None)
    return value.expandtabs(tabsize)


_STR_METHODS: Final[dict[str, Callable[..., Any]]] = {
    name: getattr(str, name)
    for name in [
        "capitalize",
        "casefold",
        "count",
        "endswith",
        "find",
        "index",
        "isalnum",
        "isalpha",
        "isascii",
        "isdecimal",
        "isdigit",
        "isidentifier",
        "islower",
        "isnumeric",
        "isprintable",
        "isspace",
        "istitle",
        "isupper",
        "lower",
        "lstrip",
        "partition",
        "removeprefix",
        "removesuffix",
        "rfind",
        "rindex",
        "rpartition",
        "rsplit",
        "rstrip",
        "split",
        "splitlines",
        "startswith",
        "strip",
        "swapcase",
        "title",
        "upper",
    ]
}
_STR_METHODS.update(
    format=_format,
    format_map=_format_map,
    join=_join,
    replace=_replace,
    center=_width(str.center),
    ljust=_width(str.ljust),
    rjust=_width(str.rjust),
    zfill=_width(str.zfill),
    expandtabs=_expandtabs,
)
_SEQ_METHODS: Final[dict[str, Callable[..., Any]]] = {"count": list.count, "index": list.index}
_TUPLE_METHODS: Final[dict[str, Callable[..., Any]]] = {"count": tuple.count, "index": tuple.index}
_DICT_METHODS: Final[dict[str, Callable[..., Any]]] = {
    "get": dict.get,
    "keys": dict.keys,
    "values": dict.values,
    "items": dict.items,
}
_METHODS: Final[dict[type, dict[str, Callable[..., Any]]]] = {
    str: _STR_METHODS,
    list: _SEQ_METHODS,
    YamlList: _SEQ_METHODS,
    tuple: _TUPLE_METHODS,
    dict: _DICT_METHODS,
    YamlDict: _DICT_METHODS,
}
_NUMBER_TYPES: Final = frozenset({int, float, complex, bool})
_NUMBER_ATTRS: Final = frozenset({"real", "imag", "numerator", "denominator"})
_NUMBER_METHODS: Final = frozenset(
    {"conjugate", "is_integer", "bit_length", "as_integer_ratio", "hex"}
)

_NOT_EXPOSED: Final = frozenset(
    [
        "type",
        "vars",
        "getattr",
        "setattr",
        "delattr",
        "eval",
        "exec",
        "compile",
        "open",
        "globals",
        "locals",
        "dir",
        "object",
        "id",
        "super",
        "input",
        "breakpoint",
        "memoryview",
        "classmethod",
        "staticmethod",
        "property",
        "help",
        "exit",
        "quit",
        "format",
        "iter",
        "next",
        "bytearray",
    ]
)


def attribute(value: Any, name: str, offset: int | None) -> Any:
    t = type(value)
    if t is YamlDict:
        method = _DICT_METHODS.get(name)
        return _Bound(method, value) if method is not None else value.__getattr__(name)
    methods = _METHODS.get(t)
    if methods is not None:
        method = methods.get(name)
        if method is not None:
            return _Bound(method, value)
    elif isinstance(value, Namespace):
        try:
            return value[name]
        except KeyError:
            if name in _NOT_EXPOSED:
                refuse(f"'{name}' is not available in expressions", offset)
            msg = f"name '{name}' is not defined"
            raise NameError(msg, name=name) from None
    elif t in _NUMBER_TYPES:
        if name in _NUMBER_ATTRS:
            return getattr(value, name)
        if name in _NUMBER_METHODS and hasattr(t, name):
            return _Bound(getattr(t, name), value)
    msg = f"attribute '{name}' of a {t.__name__} value is not available in expressions"
    raise RefusedError(msg, offset)


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
