"""A reconfigurable node's parameters as dynamic_reconfigure describes them: names, types,
levels, ranges, enums and groups; the ``ConfigDescription`` and ``Config`` messages (as plain
data, for either message flavour); and the server's rules — clamping to min/max, refusing a
value outside an enum, the level ORed over the parameters that changed."""

from __future__ import annotations

import ast
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any, Final

from belvedere.errors import BelvedereError

__all__ = [
    "TYPES",
    "Description",
    "Group",
    "Param",
    "ReconfigureError",
    "config_data",
    "config_values",
    "enum_edit_method",
    "typed",
]

TYPES: Final = {"int": int, "double": float, "str": str, "bool": bool}
"""dynamic_reconfigure's parameter types and their Python types."""

_INT_MIN: Final = -0x80000000
_INT_MAX: Final = 0x7FFFFFFF
_LIMITS: Final[dict[str, tuple[Any, Any]]] = {
    "int": (_INT_MIN, _INT_MAX),
    "double": (-math.inf, math.inf),
    "str": ("", ""),
    "bool": (False, True),
}
_DEFAULTS: Final[dict[str, Any]] = {"int": 0, "double": 0.0, "str": "", "bool": False}


class ReconfigureError(BelvedereError):
    """A value or a description that dynamic_reconfigure cannot take."""


def typed(name: str, kind: str, value: Any, what: str = "value") -> Any:
    """``value`` as parameter ``name`` of type ``kind`` holds it (an int is a fine double).

    Raises:
        ReconfigureError: it is another type, or a NaN.
    """
    want = TYPES[kind]
    if isinstance(value, bool) and want is not bool:
        ok = False
    elif want is float:
        ok = isinstance(value, int | float)
    else:
        ok = type(value) is want
    if not ok:
        msg = f"parameter {name!r} is a {kind}, but its {what} is {value!r}"
        raise ReconfigureError(msg)
    if want is float and math.isnan(value):
        msg = f"parameter {name!r}: its {what} is NaN, which no range can hold"
        raise ReconfigureError(msg)
    return want(value)


def enum_edit_method(constants: list[dict[str, Any]], description: str) -> str:
    """The ``edit_method`` text of an enum, as the generator writes it (a Python literal)."""
    return repr({"enum": constants, "enum_description": description})


@dataclass(frozen=True)
class Param:
    """One parameter: ``min``/``max`` are ``""`` for strings, as in ROS."""

    name: str
    type: str
    level: int
    description: str
    default: Any
    min: Any
    max: Any
    edit_method: str = ""

    @staticmethod
    def make(
        name: str,
        kind: str,
        level: int,
        description: str,
        default: Any = None,
        min: Any = None,
        max: Any = None,
        edit_method: str = "",
    ) -> Param:
        """A parameter as ``gen.add`` takes it: missing bounds and default are the type's."""
        if kind not in TYPES:
            msg = f"parameter {name!r}: unknown type {kind!r}"
            raise ReconfigureError(msg, hint="one of int_t, double_t, str_t, bool_t")
        if kind in ("str", "bool") and (min is not None or max is not None):
            msg = f"parameter {name!r} is a {kind}: it takes no min or max"
            raise ReconfigureError(msg)
        if (
            not name
            or not (name[0].isascii() and name[0].isalpha())
            or not all(c.isascii() and (c.isalnum() or c == "_") for c in name)
        ):
            msg = f"parameter name {name!r} is not a ROS name (a letter, then letters, digits, _)"
            raise ReconfigureError(msg)
        if type(level) is not int or level < 0:
            msg = f"parameter {name!r}: its level must be a non-negative int, not {level!r}"
            raise ReconfigureError(msg)
        low, high = _LIMITS[kind]
        return Param(
            name,
            kind,
            level,
            str(description),
            _DEFAULTS[kind] if default is None else typed(name, kind, default, "default"),
            low if min is None else typed(name, kind, min, "min"),
            high if max is None else typed(name, kind, max, "max"),
            str(edit_method),
        )

    @property
    def enum(self) -> dict[Any, str]:
        """The enum's values and their names (empty without an enum)."""
        if not self.edit_method:
            return {}
        try:  # a literal, never evaluated code (ROS's client calls eval on it)
            data = ast.literal_eval(self.edit_method)
            return {c["value"]: c["name"] for c in data["enum"]}
        except (ValueError, SyntaxError, TypeError, KeyError):
            return {}

    def accept(self, value: Any) -> Any:
        """``value`` typed, clamped to the range and checked against the enum.

        Raises:
            ReconfigureError: the wrong type, or not one of the enum's values.
        """
        value = typed(self.name, self.type, value)
        if self.type in ("int", "double"):
            value = min(max(value, self.min), self.max)
        enum = self.enum
        if enum and value not in enum:
            names = ", ".join(f"{n} ({v!r})" for v, n in enum.items())
            msg = f"parameter {self.name!r}: {value!r} is none of its enum's values"
            raise ReconfigureError(msg, hint=f"one of {names}")
        return value

    def as_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "type": self.type,
            "default": self.default,
            "level": self.level,
            "description": self.description,
            "min": self.min,
            "max": self.max,
            "edit_method": self.edit_method,
        }


@dataclass
class Group:
    """A group of parameters (``id`` 0 is the root, ``Default``)."""

    name: str
    type: str = ""
    state: bool = True
    id: int = 0
    parent: int = 0
    params: list[Param] = field(default_factory=list)
    groups: list[Group] = field(default_factory=list)

    def walk(self) -> Iterator[Group]:
        yield self
        for group in self.groups:
            yield from group.walk()

    def as_dict(self) -> dict[str, Any]:
        """The group as the generated module's ``config_description`` holds it."""
        return {
            "name": self.name,
            "type": self.type,
            "state": self.state,
            "id": self.id,
            "parent": self.parent,
            "parameters": [p.as_dict() for p in self.params],
            "groups": [g.as_dict() for g in self.groups],
        }


@dataclass
class Description:
    """A ``<Name>Config``: its groups and parameters, and the enum constants it names."""

    name: str
    root: Group
    constants: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        seen: set[str] = set()
        for param in self.params():
            if param.name in seen:
                msg = f"parameter {param.name!r} is added twice"
                raise ReconfigureError(msg)
            seen.add(param.name)

    def params(self) -> list[Param]:
        return [p for g in self.root.walk() for p in g.params]

    def param(self, name: str) -> Param:
        for p in self.params():
            if p.name == name:
                return p
        known = ", ".join(p.name for p in self.params())
        msg = f"{self.name} has no parameter {name!r}"
        raise ReconfigureError(msg, hint=f"its parameters: {known}")

    @property
    def defaults(self) -> dict[str, Any]:
        return {p.name: p.default for p in self.params()}

    def merged(self, config: Mapping[str, Any], changes: Mapping[str, Any]) -> dict[str, Any]:
        """``config`` with ``changes`` accepted over it (unknown names refused)."""
        out = dict(config)
        for name, value in changes.items():
            out[name] = self.param(name).accept(value)
        return out

    def level(self, new: Mapping[str, Any], old: Mapping[str, Any]) -> int:
        """The levels of the parameters whose values differ, ORed."""
        level = 0
        for p in self.params():
            if new.get(p.name) != old.get(p.name):
                level |= p.level
        return level

    def group_states(self) -> list[dict[str, Any]]:
        return [
            {"name": g.name, "state": g.state, "id": g.id, "parent": g.parent}
            for g in self.root.walk()
        ]

    def message_data(self) -> dict[str, Any]:
        """``dynamic_reconfigure/ConfigDescription`` as data."""
        groups = [
            {
                "name": g.name,
                "type": g.type,
                "parent": g.parent,
                "id": g.id,
                "parameters": [
                    {
                        "name": p.name,
                        "type": p.type,
                        "level": p.level,
                        "description": p.description,
                        "edit_method": p.edit_method,
                    }
                    for p in g.params
                ],
            }
            for g in self.root.walk()
        ]
        states = self.group_states()
        ps = self.params()
        return {
            "groups": groups,
            "max": config_data({p.name: p.max for p in ps}, states),
            "min": config_data({p.name: p.min for p in ps}, states),
            "dflt": config_data(self.defaults, states),
        }


def config_data(values: Mapping[str, Any], groups: list[dict[str, Any]]) -> dict[str, Any]:
    """``dynamic_reconfigure/Config`` as data: each value in the list of its type."""
    out: dict[str, list[dict[str, Any]]] = {"bools": [], "ints": [], "strs": [], "doubles": []}
    for name, value in values.items():
        kind = (
            "bools"
            if isinstance(value, bool)
            else "ints"
            if isinstance(value, int)
            else "doubles"
            if isinstance(value, float)
            else "strs"
        )
        out[kind].append({"name": name, "value": value})
    return {**out, "groups": [dict(g) for g in groups]}


def config_values(data: Mapping[str, Any]) -> dict[str, Any]:
    """The values of a ``Config`` (as data), in ROS's order: bools, ints, strs, doubles."""
    return {
        item["name"]: item["value"]
        for kind in ("bools", "ints", "strs", "doubles")
        for item in data.get(kind, [])
    }
