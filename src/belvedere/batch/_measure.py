"""What a batch run reports: columns computed from the messages a run's topics carried.

``record:`` columns are a field of a topic's last message (``/odom pose.pose.position.x``);
``metrics:`` columns are ``max``/``min``/``mean``/``last`` of a field over the run,
``count`` of a topic's messages, ``time`` to a condition (the simulated time, from the
message's ``header.stamp``, of the first message where ``FIELD OP VALUE`` holds), or
``python FILE:FUNCTION TOPIC…``: a user's function given every message of those topics.
"""

from __future__ import annotations

import importlib.util
import math
import operator
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph import resolve_name

__all__ = ["Measure", "MeasureError", "evaluate", "parse_measure"]

Messages = Mapping[str, Sequence[Any]]
"""topic → its messages in order, each as ``topic echo`` prints it (a YAML mapping)."""

_KINDS = ("max", "min", "mean", "last", "count", "time", "python")
_OPS: dict[str, Callable[[Any, Any], bool]] = {
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
    "==": operator.eq,
    "!=": operator.ne,
}


class MeasureError(BelvedereError):
    """A column that a run's messages cannot give (a field they lack, a function that raised)."""


@dataclass(frozen=True)
class Measure:
    """One column: ``kind`` over ``topics`` (one, but for ``python``)."""

    name: str
    kind: str
    topics: tuple[str, ...]
    field: str = ""
    op: str = ""
    threshold: float = 0.0
    function: str = ""
    """``python``: ``FILE:FUNCTION``, FILE relative to the spec's folder."""


def parse_measure(name: str, text: str, *, record: bool) -> Measure:
    """The column ``name`` as the spec writes it (``record``: ``TOPIC FIELD``)."""
    words = text.split()
    if record:
        if len(words) != 2:
            msg = f"record: {name}: expects 'TOPIC FIELD', got {text!r}"
            raise BelvedereError(msg, hint="e.g. x: /odom pose.pose.position.x")
        return Measure(name, "last", (resolve_name(words[0]),), _field(words[1]))
    kind = words[0] if words else ""
    if kind not in _KINDS:
        msg = f"metrics: {name}: unknown metric {kind!r}"
        raise BelvedereError(msg, hint=f"a metric is one of {', '.join(_KINDS)}, then its topic")
    args = words[1:]
    if kind == "count":
        if len(args) != 1:
            msg = f"metrics: {name}: expects 'count TOPIC', got {text!r}"
            raise BelvedereError(msg)
        return Measure(name, kind, (resolve_name(args[0]),))
    if kind == "python":
        if len(args) < 2 or ":" not in args[0]:
            msg = f"metrics: {name}: expects 'python FILE.py:FUNCTION TOPIC…', got {text!r}"
            raise BelvedereError(msg, hint="the function gets {topic: [messages]}")
        return Measure(name, kind, tuple(resolve_name(t) for t in args[1:]), function=args[0])
    if kind == "time":
        if len(args) != 4 or args[2] not in _OPS:
            msg = f"metrics: {name}: expects 'time TOPIC FIELD OP VALUE', got {text!r}"
            raise BelvedereError(msg, hint=f"OP is one of {' '.join(_OPS)}")
        try:
            threshold = float(args[3])
        except ValueError:
            msg = f"metrics: {name}: {args[3]!r} is not a number"
            raise BelvedereError(msg) from None
        return Measure(name, kind, (resolve_name(args[0]),), _field(args[1]), args[2], threshold)
    if len(args) != 2:
        msg = f"metrics: {name}: expects '{kind} TOPIC FIELD', got {text!r}"
        raise BelvedereError(msg)
    return Measure(name, kind, (resolve_name(args[0]),), _field(args[1]))


def _field(path: str) -> str:
    if not path or any(not part for part in path.split(".")):
        msg = f"{path!r} is not a field path (e.g. pose.pose.position.x)"
        raise BelvedereError(msg)
    return path


def field_of(msg: Any, path: str, topic: str) -> Any:
    """The value at ``path`` (``a.b.0.c``: a number indexes a list) of ``msg``."""
    value = msg
    for part in path.split("."):
        if isinstance(value, Mapping) and part in value:
            value = value[part]
        elif (
            isinstance(value, list)
            and part.lstrip("-").isdigit()
            and -len(value) <= int(part) < len(value)
        ):
            value = value[int(part)]
        else:
            known = ", ".join(value) if isinstance(value, Mapping) else type(value).__name__
            msg = f"{topic}'s messages have no field {path!r} (at {part!r}: {known})"
            raise MeasureError(msg)
    return value


def _number(value: Any, measure: Measure) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        msg = f"{measure.name}: {measure.field} is not a number ({value!r})"
        raise MeasureError(msg)
    return float(value)


def _stamp(msg: Any, topic: str) -> float:
    stamp = field_of(msg, "header.stamp", topic)
    return float(stamp["secs"]) + float(stamp["nsecs"]) * 1e-9


def evaluate(measure: Measure, messages: Messages, folder: Path) -> Any:
    """The column's value for one run (None: the run gave none, e.g. no message arrived)."""
    if measure.kind == "python":
        return _call(measure, messages, folder)
    msgs = messages.get(measure.topics[0], ())
    if measure.kind == "count":
        return len(msgs)
    if not msgs:
        return None
    if measure.kind == "last":
        return field_of(msgs[-1], measure.field, measure.topics[0])
    if measure.kind == "time":
        test = _OPS[measure.op]
        for msg in msgs:
            value = _number(field_of(msg, measure.field, measure.topics[0]), measure)
            if test(value, measure.threshold):
                return _stamp(msg, measure.topics[0])
        return None
    values = [_number(field_of(m, measure.field, measure.topics[0]), measure) for m in msgs]
    if measure.kind == "max":
        return max(values)
    if measure.kind == "min":
        return min(values)
    return math.fsum(values) / len(values)


def _call(measure: Measure, messages: Messages, folder: Path) -> Any:
    file, _, name = measure.function.rpartition(":")
    path = folder / file
    if not path.is_file():
        msg = f"{measure.name}: no file {file} (in {folder})"
        raise MeasureError(msg)
    spec = importlib.util.spec_from_file_location(f"belvedere_batch_metric_{path.stem}", path)
    if spec is None or spec.loader is None:
        msg = f"{measure.name}: {file} is not a Python file"
        raise MeasureError(msg)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
        function = getattr(module, name)
        return function({t: list(messages.get(t, ())) for t in measure.topics})
    except Exception as err:  # noqa: BLE001  # the user's code: any failure is this column's error, said
        msg = f"{measure.name}: {file}:{name} raised {type(err).__name__}: {err}"
        raise MeasureError(msg) from None
