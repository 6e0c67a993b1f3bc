"""Typed reads of ROS parameters from plain mappings, shared by the navigation algorithms."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["ParamReader", "read_fields"]


class ParamReader:
    """Typed look-ups over a parameter mapping; a wrong value raises ``ValueError`` naming it."""

    def __init__(self, values: Mapping[str, Any]) -> None:
        self.values = values

    def _raw(self, names: Sequence[str]) -> tuple[str, Any] | None:
        for name in names:
            if name in self.values:
                return name, self.values[name]
        return None

    def has(self, *names: str) -> bool:
        return self._raw(names) is not None

    def number(self, default: float, *names: str) -> float:
        found = self._raw(names)
        if found is None:
            return default
        name, raw = found
        if isinstance(raw, bool) or not isinstance(raw, int | float) or not math.isfinite(raw):
            message = f"parameter {name}: expected a number, got {raw!r}"
            raise ValueError(message)
        return float(raw)

    def whole(self, default: int, *names: str) -> int:
        found = self._raw(names)
        if found is None:
            return default
        name, raw = found
        if isinstance(raw, bool) or not (
            isinstance(raw, int) or (isinstance(raw, float) and raw.is_integer())
        ):
            message = f"parameter {name}: expected a whole number, got {raw!r}"
            raise ValueError(message)
        return int(raw)

    def flag(self, default: bool, *names: str) -> bool:
        found = self._raw(names)
        if found is None:
            return default
        name, raw = found
        if not isinstance(raw, bool):
            message = f"parameter {name}: expected true or false, got {raw!r}"
            raise ValueError(message)
        return raw

    def frame(self, default: str, *names: str) -> str:
        """A frame's name, without tf1's leading (or a stray trailing) slash."""
        found = self._raw(names)
        raw = default if found is None else found[1]
        if not isinstance(raw, str) or not raw.strip("/"):
            name = names[0] if found is None else found[0]
            message = f"parameter {name}: expected a frame name, got {raw!r}"
            raise ValueError(message)
        return raw.strip("/")

    def numbers(self, default: tuple[float, ...], name: str) -> tuple[float, ...]:
        """A list of numbers, as a YAML list or as the string ``"[-0.3, -0.1, 0.1]"``
        (TrajectoryPlannerROS reads ``y_vels`` as a string and splits it at ``[``, ``]``,
        commas and spaces)."""
        found = self._raw((name,))
        if found is None:
            return default
        raw = found[1]
        items: list[Any]
        if isinstance(raw, str):
            items = list(raw.replace("[", " ").replace("]", " ").replace(",", " ").split())
        elif isinstance(raw, list | tuple):
            items = list(raw)
        else:
            items = [raw]
        values: list[float] = []
        for item in items:
            try:
                if isinstance(item, bool):
                    raise ValueError
                value = float(item)
            except (TypeError, ValueError):
                message = f"parameter {name}: expected a list of numbers, got {raw!r}"
                raise ValueError(message) from None
            values.append(value)
        return tuple(values)


def read_like(read: ParamReader, defaults: Mapping[str, Any]) -> dict[str, Any]:
    """Each parameter of ``defaults`` read as its default's kind: a flag, a number or (a
    string) a frame name."""
    out: dict[str, Any] = {}
    for name, default in defaults.items():
        if isinstance(default, bool):
            out[name] = read.flag(default, name)
        elif isinstance(default, int | float):
            out[name] = read.number(float(default), name)
        else:
            out[name] = read.frame(str(default), name)
    return out


def read_fields(
    cls: type[Any],
    read: ParamReader,
    aliases: Mapping[str, tuple[str, ...]],
    given: Mapping[str, Any],
) -> dict[str, Any]:
    """Every field of the dataclass ``cls`` read under its own name, then its older
    ``aliases``, defaulting to the field's default; its default's kind decides the read (a
    flag, a whole number, a number, a list of numbers). Fields in ``given`` are taken as
    they are (those ROS works out from other parameters)."""
    fields: dict[str, Any] = {}
    for field in dataclasses.fields(cls):
        name, default = field.name, field.default
        names = (name, *aliases.get(name, ()))
        if name in given:
            fields[name] = given[name]
        elif isinstance(default, bool):
            fields[name] = read.flag(default, *names)
        elif isinstance(default, int):
            fields[name] = read.whole(default, *names)
        elif isinstance(default, float):
            fields[name] = read.number(default, *names)
        elif isinstance(default, tuple):
            fields[name] = read.numbers(default, name)
        else:
            message = f"{cls.__name__}.{name}: no parameter read for its kind of default"
            raise TypeError(message)
    return fields
