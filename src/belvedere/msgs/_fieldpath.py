"""Numeric fields of messages named by path, as rqt_plot names them on its command line:
``/odom/pose/pose/position/x``, ``/joint_states/position[0]``, ``/turtle1/pose/x:y`` (two
fields of one message), several separated by spaces or commas; a path that ends at a message
(``/turtle1/pose``) stands for its numeric fields.

Which part of a path is the topic is only known from the graph (``/a/b/c`` may be the field
``c`` of ``/a/b``), so :func:`split_plot_args` keeps whole paths and :func:`resolve_series`
splits one against the topics the graph has.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Iterable, Mapping
from typing import Any, Final

import numpy as np

from belvedere.errors import BelvedereError
from belvedere.msgs._convert import default_message

__all__ = [
    "FieldPathError",
    "Series",
    "field_value",
    "resolve_series",
    "split_plot_args",
]

_STEP: Final = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)(?:\[(\d+)\])?$")
_NUMERIC: Final = (bool, int, float, np.integer, np.floating, np.bool_)


class FieldPathError(BelvedereError):
    """A path that names no numeric field of its topic's messages."""


@dataclasses.dataclass(frozen=True, slots=True)
class Series:
    """One plotted field: its topic, type and the steps from the message to the number."""

    topic: str
    msg_type: str
    steps: tuple[tuple[str, int | None], ...]

    @property
    def label(self) -> str:
        """The path as rqt_plot's legend shows it: ``/odom/pose/pose/position/x``."""
        parts = [name if index is None else f"{name}[{index}]" for name, index in self.steps]
        return "/".join([self.topic.rstrip("/"), *parts])


def split_plot_args(words: Iterable[str]) -> list[str]:
    """The field paths rqt_plot's arguments name: separated by spaces or commas, a last step
    ``a:b`` standing for the paths to ``a`` and to ``b`` beside it."""
    paths: list[str] = []
    for word in words:
        for part in word.split(","):
            part = part.strip()
            if not part:
                continue
            if not part.startswith("/"):
                part = "/" + part  # rqt_plot takes names relative to the root namespace
            head, _, last = part.rpartition("/")
            paths.extend(f"{head}/{name}" for name in last.split(":") if name)
    return paths


def _steps(path: str, text: str) -> tuple[tuple[str, int | None], ...]:
    steps: list[tuple[str, int | None]] = []
    for word in [w for w in text.split("/") if w]:
        match = _STEP.match(word)
        if match is None:
            msg = f"{path}: {word!r} is no field name (expected name or name[index])"
            raise FieldPathError(msg)
        index = match.group(2)
        steps.append((match.group(1), None if index is None else int(index)))
    return tuple(steps)


def _topic_of(path: str, topics: Mapping[str, str]) -> str | None:
    """The longest topic that ``path`` starts with, by whole names."""
    best: str | None = None
    for topic in topics:
        name = topic.rstrip("/")
        if (path == name or path.startswith(name + "/")) and (
            best is None or len(name) > len(best)
        ):
            best = name
    return best


def _fields(value: Any) -> list[str]:
    """A message's field names (rosbags' classes also carry ``__msgtype__``)."""
    return [f.name for f in dataclasses.fields(value) if not f.name.startswith("__")]


def _numeric(value: Any) -> bool:
    return isinstance(value, _NUMERIC)


def _walk(path: str, value: Any, steps: Iterable[tuple[str, int | None]]) -> Any:
    """Follow ``steps`` through a default message; errors name what the path expected."""
    for name, index in steps:
        if not dataclasses.is_dataclass(value) or name not in _fields(value):
            fields = (
                ", ".join(_fields(value))
                if dataclasses.is_dataclass(value)
                else "none: it is a number"
            )
            msg = f"{path}: no field {name!r} (fields here: {fields})"
            raise FieldPathError(msg)
        value = getattr(value, name)
        is_array = isinstance(value, (list, tuple, np.ndarray))
        if index is not None and not is_array:
            msg = f"{path}: {name!r} is not an array; [{index}] names nothing"
            raise FieldPathError(msg)
        if is_array:
            if index is None:
                msg = f"{path}: {name!r} is an array: name an element, as {name}[0]"
                raise FieldPathError(msg)
            # Variable-length arrays are empty in a default message: what they hold is known
            # from their type only for numbers, and an element checked here would be a guess.
            value = value[index] if index < len(value) else None
    return value


def resolve_series(path: str, topics: Mapping[str, str]) -> list[Series] | None:
    """The series ``path`` names on the graph whose published ``topics`` (name → type) are
    given; None while no topic of the path is published (rqt_plot waits for it). A path that
    ends at a message gives its numeric fields.

    Raises:
        FieldPathError: the topic's messages have no numeric field at that path.
    """
    topic = _topic_of(path, topics)
    if topic is None:
        return None
    msg_type = topics[topic] if topic in topics else topics[topic + "/"]
    steps = _steps(path, path[len(topic) :])
    leaf = _walk(path, default_message(msg_type), steps)
    if leaf is None or _numeric(leaf):
        return [Series(topic, msg_type, steps)]
    if dataclasses.is_dataclass(leaf):
        numeric = [name for name in _fields(leaf) if _numeric(getattr(leaf, name))]
        if numeric:
            return [Series(topic, msg_type, (*steps, (name, None))) for name in numeric]
    msg = f"{path}: not a number (a {type(leaf).__name__}); name a numeric field below it"
    raise FieldPathError(msg)


def field_value(msg: Any, steps: tuple[tuple[str, int | None], ...]) -> float | None:
    """The number at ``steps`` in ``msg``; None when an array is shorter than its index or
    the value is not finite (a gap in the plot, as rqt_plot leaves)."""
    value = msg
    for name, index in steps:
        value = getattr(value, name)
        if index is not None:
            if index >= len(value):
                return None
            value = value[index]
    number = float(value)
    return number if math.isfinite(number) else None
