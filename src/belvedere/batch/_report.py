"""A batch's output: its progress on stderr, its rows as CSV, and a summary plot."""

from __future__ import annotations

import csv
import json
import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, TextIO

from belvedere.batch._execute import Row
from belvedere.batch._spec import BatchSpec
from belvedere.errors import BelvedereError

__all__ = ["Progress", "cell", "plot_rows", "write_csv"]


class Progress:
    """``batch: 3/12 done, 1 failed, ETA 0:00:42`` — on one line rewritten on a terminal, a
    line per run elsewhere (a log)."""

    def __init__(self, total: int, stream: TextIO) -> None:
        self.total = total
        self.stream = stream
        self.done = 0
        self.failed = 0
        self.started = time.monotonic()
        self.tty = stream.isatty()

    def __call__(self, row: Row) -> None:
        self.done += 1
        self.failed += row.get("status") != "ok"
        elapsed = time.monotonic() - self.started
        left = (self.total - self.done) * elapsed / self.done
        line = f"batch: {self.done}/{self.total} done, {self.failed} failed, ETA {_clock(left)}"
        if row.get("status") != "ok":
            line += f" (run {row['run']}: {row.get('status')}: {row.get('error')})"
        end = "\n" if not self.tty or self.done == self.total else ""
        self.stream.write(("\r\x1b[K" if self.tty else "") + line + end)
        self.stream.flush()


def _clock(seconds: float) -> str:
    s = round(seconds)
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"


def cell(value: Any) -> str:
    """A value as its CSV cell: empty for none, a float's shortest exact text, a message's
    part as JSON."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, dict | list):
        return json.dumps(value, sort_keys=True)
    return str(value)


def write_csv(path: Path, spec: BatchSpec, rows: Sequence[Row]) -> None:
    with path.open("w", newline="", encoding="utf-8") as out:
        writer = csv.writer(out)
        writer.writerow(spec.columns)
        for row in rows:
            writer.writerow([cell(row.get(c)) for c in spec.columns])


def plot_rows(path: Path, spec: BatchSpec, rows: Sequence[Row]) -> None:
    """Each numeric measure against each varied value: a grid of scatter plots (a varied
    value that is not a number is spread as categories)."""
    try:
        import matplotlib  # an optional extra: only --plot needs it

        matplotlib.use("Agg")
        from matplotlib import pyplot
    except ImportError:
        msg = "--plot needs matplotlib, which is not installed"
        raise BelvedereError(msg, hint="pip install 'belvedere[plot]'") from None
    measures = [m.name for m in spec.measures if any(_number(r.get(m.name)) for r in rows)]
    varied = list(spec.varied) or ["run"]
    if not measures:
        msg = "--plot: no column has a number to plot (every run failed, or none recorded)"
        raise BelvedereError(msg)
    fig, axes = pyplot.subplots(
        len(measures), len(varied), squeeze=False, figsize=(4 * len(varied), 3 * len(measures))
    )
    for i, measure in enumerate(measures):
        for j, column in enumerate(varied):
            ax = axes[i][j]
            xs = [cell(r.get(column)) for r in rows]
            ys = [_number(r.get(measure)) for r in rows]
            ticks = sorted(set(xs), key=_sort_key)
            numeric = all(_number(x) is not None for x in ticks)
            pts = [
                (float(x) if numeric else ticks.index(x), y)
                for x, y in zip(xs, ys, strict=True)
                if y is not None
            ]
            ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=18)
            if not numeric:
                ax.set_xticks(range(len(ticks)), [t[:24] for t in ticks], rotation=20)
            ax.set_xlabel(column)
            ax.set_ylabel(measure)
            ax.grid(True, alpha=0.3)
    fig.suptitle(f"{spec.path.name}: {len(rows)} runs")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    pyplot.close(fig)


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or value is None:
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


def _sort_key(text: str) -> tuple[int, float, str]:
    number = _number(text)
    return (0, number, "") if number is not None else (1, 0.0, text)
