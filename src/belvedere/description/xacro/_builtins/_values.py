"""The values expressions make and reach: namespaces, YAML data with dotted access, lambdas
and their frames, bound methods and exposed host functions."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

from belvedere.description.xacro._bounds import MAX_CALLS, budget, charge, refuse
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
    "expose",
    "to_yaml_value",
]


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
