"""A batch spec (``belvedere batch SPEC.yaml``) read and checked, and the runs it describes.

The spec names what one run is (``sim:`` or ``launch:``, a ``duration`` of simulated time),
which values vary (``runs:``: the cartesian product of every list in it) and what each run
reports (``record:``, ``metrics:``). Every mistake is one error at the spec's file and line.
"""

from __future__ import annotations

import itertools
import math
import shlex
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from belvedere.batch._measure import Measure, parse_measure
from belvedere.errors import BelvedereError, ParseError
from belvedere.graph import resolve_name
from belvedere.msgs import message_from_args, types
from belvedere.yamlfile import YamlDocument, load_yaml_file

__all__ = ["BatchSpec", "RunDescription", "read_spec"]

DEFAULT_TIMEOUT = 600.0
"""Wall-clock seconds one run may take before it is stopped and reported ``timeout``."""

_KEYS = ("sim", "launch", "duration", "timeout", "runs", "record", "metrics", "goal", "bag")
_RUN_KEYS = ("args", "params", "pub", "seed")


@dataclass(frozen=True)
class RunDescription:
    """One run, everything needed to start it on any machine that has the spec's folder.

    Paths in ``command`` are as the spec wrote them: relative to the spec's folder, which is
    the run's working directory (on a Ray worker: the folder Ray shipped)."""

    index: int
    kind: str
    """``sim`` or ``launch``"""
    command: tuple[str, ...]
    """The words after ``belvedere sim``/``belvedere launch``."""
    duration: float
    timeout: float
    seed: int
    args: tuple[tuple[str, str], ...] = ()
    params: tuple[tuple[str, Any], ...] = ()
    pubs: tuple[str, ...] = ()
    measures: tuple[Measure, ...] = ()
    bag: bool = False
    values: tuple[tuple[str, str], ...] = ()
    """The varied values, as the CSV's columns show them (column, value)."""


@dataclass(frozen=True)
class BatchSpec:
    """A checked spec: its folder (each run's working directory) and its runs."""

    path: Path
    folder: Path
    runs: tuple[RunDescription, ...]
    varied: tuple[str, ...]
    """The varied columns, in the spec's order."""
    measures: tuple[Measure, ...] = field(default=())

    @property
    def columns(self) -> tuple[str, ...]:
        """The CSV's columns: run id, varied values, outcome, then every measure."""
        return (
            "run",
            *self.varied,
            "status",
            "error",
            "wall_s",
            *(m.name for m in self.measures),
        )


def read_spec(path: str | Path) -> BatchSpec:
    """The spec at ``path``, checked: an error names its file and line."""
    doc = load_yaml_file(path)
    return _Reader(doc, Path(path)).spec()


class _Reader:
    def __init__(self, doc: YamlDocument, path: Path) -> None:
        self.doc = doc
        self.path = path

    def fail(self, message: str, *keys: str | int, hint: str | None = None) -> ParseError:
        return ParseError(message, self.doc.location(*keys), hint=hint)

    def spec(self) -> BatchSpec:
        data = self.doc.data
        if not isinstance(data, dict):
            msg = "a batch spec is a mapping (sim: or launch:, duration:, runs: …)"
            raise self.fail(msg)
        for key in data:
            if key not in _KEYS:
                msg = f"unknown key {key!r} in a batch spec"
                raise self.fail(
                    msg,
                    str(key),
                    hint=f"the keys are {', '.join(_KEYS)}",
                )
        kind, command = self._command(data)
        duration = self._positive(data, "duration", required=True)
        timeout = self._positive(data, "timeout") or DEFAULT_TIMEOUT
        measures = self._measures(data)
        goal = self._goal(data.get("goal"))
        bag = data.get("bag", False)
        if not isinstance(bag, bool):
            msg = "bag: expects true or false"
            raise self.fail(msg, "bag")
        if bag and kind != "launch":
            msg = "bag: true needs launch: (the bag is recorded by a rosbag node beside the run's)"
            raise self.fail(msg, "bag")
        dims = self._dimensions(data.get("runs") or {}, kind)
        runs = []
        for index, combo in enumerate(itertools.product(*(values for _, values in dims))):
            chosen = dict(zip((name for name, _ in dims), combo, strict=True))
            runs.append(
                RunDescription(
                    index=index,
                    kind=kind,
                    command=command,
                    duration=duration,
                    timeout=timeout,
                    seed=int(chosen.get("seed", 0)),
                    args=tuple(
                        (n[len("arg:") :], _text(v)) for n, v in chosen.items() if n[:4] == "arg:"
                    ),
                    params=tuple(
                        (n[len("param:") :], v) for n, v in chosen.items() if n[:6] == "param:"
                    ),
                    pubs=(*_pubs(chosen.get("pub")), *goal),
                    measures=measures,
                    bag=bag,
                    values=tuple((n, _text(v)) for n, v in chosen.items()),
                )
            )
        return BatchSpec(
            path=self.path,
            folder=self.path.resolve().parent,
            runs=tuple(runs),
            varied=tuple(name for name, _ in dims),
            measures=measures,
        )

    def _command(self, data: dict[str, Any]) -> tuple[str, tuple[str, ...]]:
        given = [k for k in ("sim", "launch") if k in data]
        if len(given) != 1:
            msg = "a batch spec names one of sim: or launch: (what one run is)"
            raise self.fail(
                msg,
                *(given[1:2] or []),
                hint="e.g. sim: [model.xacro, --engine, physics] or launch: PKG FILE.launch",
            )
        kind = given[0]
        value = data[kind]
        if isinstance(value, str):
            words = shlex.split(value)
        elif isinstance(value, list) and all(isinstance(w, str | int | float) for w in value):
            words = [str(w) for w in value]
        else:
            msg = f"{kind}: expects a command line (a string or a list)"
            raise self.fail(msg, kind)
        if not words:
            msg = f"{kind}: is empty"
            raise self.fail(msg, kind)
        for owned in ("--duration", "--rtf", "--seed", "--domain", "--endpoint", "--echo"):
            if owned in words:
                msg = f"{kind}: {owned} is set by the batch for every run"
                raise self.fail(
                    msg,
                    kind,
                    hint="use duration: and runs: seed: instead",
                )
        return kind, tuple(words)

    def _positive(self, data: dict[str, Any], key: str, *, required: bool = False) -> float:
        value = data.get(key)
        if value is None:
            if required:
                msg = f"{key}: is required (seconds)"
                raise self.fail(msg, hint=f"e.g. {key}: 60")
            return 0.0
        if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
            msg = f"{key}: expects a positive number of seconds, got {value!r}"
            raise self.fail(msg, key)
        if math.isinf(value):
            msg = f"{key}: expects a finite number of seconds"
            raise self.fail(msg, key)
        return float(value)

    def _measures(self, data: dict[str, Any]) -> tuple[Measure, ...]:
        measures: list[Measure] = []
        for section in ("record", "metrics"):
            table = data.get(section) or {}
            if not isinstance(table, dict):
                msg = f"{section}: expects a mapping of column: 'TOPIC FIELD'"
                raise self.fail(msg, section)
            for name, text in table.items():
                if not isinstance(text, str):
                    msg = f"{section}: {name}: expects a string"
                    raise self.fail(msg, section, str(name))
                if any(m.name == str(name) for m in measures) or str(name) in _reserved():
                    msg = f"column {name!r} is named twice"
                    raise self.fail(msg, section, str(name))
                try:
                    measures.append(parse_measure(str(name), text, record=section == "record"))
                except BelvedereError as err:
                    raise self.fail(err.message, section, str(name), hint=err.hint) from None
        return tuple(measures)

    def _goal(self, value: Any) -> tuple[str, ...]:
        if value is None:
            return ()
        words = str(value).split() if isinstance(value, str) else []
        try:
            frame, x, y, yaw = words[0], *(float(w) for w in words[1:])
        except (ValueError, IndexError):
            msg = f"goal: expects 'FRAME X Y YAW', got {value!r}"
            raise self.fail(msg, "goal", hint="goal: map 1.0 0.5 0") from None
        return (
            "/move_base_simple/goal geometry_msgs/PoseStamped "
            f"{{header: {{frame_id: {frame}}}, pose: {{position: {{x: {x!r}, y: {y!r}}}, "
            f"orientation: {{z: {math.sin(yaw / 2)!r}, w: {math.cos(yaw / 2)!r}}}}}}}",
        )

    def _dimensions(self, runs: Any, kind: str) -> list[tuple[str, list[Any]]]:
        if not isinstance(runs, dict):
            msg = "runs: expects a mapping (args:, params:, pub:, seed:)"
            raise self.fail(msg, "runs")
        dims: list[tuple[str, list[Any]]] = []
        for key, value in runs.items():
            where = ("runs", str(key))
            if key not in _RUN_KEYS:
                msg = f"unknown key {key!r} in runs:"
                raise self.fail(
                    msg,
                    *where,
                    hint=f"runs: has {', '.join(_RUN_KEYS)}",
                )
            if key in ("args", "params"):
                if not isinstance(value, dict):
                    msg = f"runs: {key}: expects a mapping of name: [values]"
                    raise self.fail(msg, *where)
                if key == "params" and kind != "launch":
                    msg = (
                        "runs: params: needs launch: (parameters are set as a launch file's "
                        "<param> are)"
                    )
                    raise self.fail(
                        msg,
                        *where,
                    )
                for name, values in value.items():
                    column = f"{key[:-1]}:{name}"
                    if key == "params":
                        try:
                            resolve_name(str(name))
                        except BelvedereError as err:
                            raise self.fail(err.message, *where, str(name)) from None
                    dims.append((column, self._values(values, *where, str(name))))
            elif key == "seed":
                values = self._values(value, *where)
                if not all(isinstance(v, int) and not isinstance(v, bool) for v in values):
                    msg = "runs: seed: expects integers"
                    raise self.fail(msg, *where)
                dims.append(("seed", values))
            else:
                values = self._values(value, *where)
                for i, item in enumerate(values):
                    self._check_pubs(item, *where, i)
                dims.append(("pub", values))
        return dims

    def _values(self, value: Any, *where: str | int) -> list[Any]:
        values = value if isinstance(value, list) else [value]
        if not values:
            msg = "an empty list of values makes no runs"
            raise self.fail(msg, *where)
        for i, item in enumerate(values):
            if isinstance(item, dict):
                msg = "a varied value is a number, a string or a list of them"
                raise self.fail(msg, *where, i)
        return values

    def _check_pubs(self, item: Any, *where: str | int) -> None:
        for spec in item if isinstance(item, list) else [item]:
            words = str(spec).split(None, 2)
            try:
                if len(words) < 2:
                    msg = f"pub: expects 'TOPIC TYPE YAML', got {spec!r}"
                    raise BelvedereError(msg)
                resolve_name(words[0])
                message_from_args(types().resolve(words[1]), words[2:])
            except BelvedereError as err:
                raise self.fail(err.message, *where, hint=err.hint) from None


def _reserved() -> set[str]:
    return {"run", "status", "error", "wall_s"}


def _pubs(value: Any) -> Sequence[str]:
    if value is None:
        return ()
    return tuple(str(v) for v in value) if isinstance(value, list) else (str(value),)


def _text(value: Any) -> str:
    if isinstance(value, list):
        return "; ".join(_text(v) for v in value)
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)
