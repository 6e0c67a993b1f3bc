"""The attributes and methods expressions may read: of strings, sequences, dicts, numbers,
YAML data and namespaces; ``str.format`` fields are plain names or positions."""

from __future__ import annotations

import re
import string
from collections.abc import Callable, Iterable, Mapping
from typing import Any, Final

from belvedere.description.xacro._bounds import (
    MAX_CHARS,
    RefusedError,
    check_spec,
    check_str,
    metered,
    refuse,
)
from belvedere.description.xacro._builtins._values import Namespace, YamlDict, YamlList, _Bound

__all__ = ["attribute"]

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
