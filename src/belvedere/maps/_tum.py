"""Trajectories in the TUM format: one pose a line, ``stamp tx ty tz qx qy qz qw``."""

from __future__ import annotations

import math
import os
from collections.abc import Iterable

import numpy as np
import numpy.typing as npt

from belvedere.bounded import LimitError, read_regular_text
from belvedere.errors import ParseError, SourceLocation

__all__ = ["TrajectoryError", "format_tum_line", "read_tum"]


class TrajectoryError(ParseError):
    """A trajectory file that cannot be read, at the line that is wrong."""


def read_tum(path: str | os.PathLike[str]) -> npt.NDArray[np.float64]:
    """The poses of a TUM file: ``(N, 8)`` rows of stamp, position, quaternion (x, y, z, w).
    Blank lines and ``#`` comments are skipped.

    Raises:
        TrajectoryError: the file cannot be read, or a line is not 8 numbers (at that line).
    """
    shown = os.fspath(path)
    try:
        text = read_regular_text(path, what="the trajectory", name=repr(shown))
    except LimitError as err:
        raise TrajectoryError(err.message, err.location) from None
    rows: list[list[float]] = []
    for number, line in enumerate(text.splitlines(), start=1):
        words = line.split("#", 1)[0].replace(",", " ").split()
        if not words:
            continue
        at = SourceLocation(shown, number, 1)
        if len(words) != 8:
            msg = f"a TUM line is 8 numbers (stamp tx ty tz qx qy qz qw), this one has {len(words)}"
            raise TrajectoryError(msg, at)
        try:
            values = [float(w) for w in words]
        except ValueError:
            bad = next(w for w in words if not _is_float(w))
            msg = f"{bad!r} is not a number"
            raise TrajectoryError(msg, at) from None
        if not all(math.isfinite(v) for v in values):
            msg = "a TUM line holds a value that is not finite"
            raise TrajectoryError(msg, at)
        rows.append(values)
    return np.array(rows, dtype=np.float64).reshape(-1, 8)


def _is_float(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def format_tum_line(stamp: float, position: Iterable[float], quat_xyzw: Iterable[float]) -> str:
    """One TUM line (with its newline)."""
    values = [stamp, *position, *quat_xyzw]
    return " ".join(f"{v:.9g}" if i else f"{v:.9f}" for i, v in enumerate(values)) + "\n"
