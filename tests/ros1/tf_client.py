"""The client side of ``tf_oracle.py``: Debian's tf and tf2_ros, run by ``/usr/bin/python3`` in
a subprocess that answers one JSON request per line, so hypothesis can ask example by example;
and the encoding both sides share."""

from __future__ import annotations

import json
import math
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.ros1.tf_steps import error

__all__ = ["TfOracle", "check_steps", "encode", "error", "missing", "oracle_fixture", "same"]

SYSTEM_PYTHON = Path("/usr/bin/python3")
SCRIPT = Path(__file__).with_name("tf_oracle.py")


def missing() -> str | None:
    """Why the oracle cannot run here, or None."""
    if not SYSTEM_PYTHON.exists():
        return f"{SYSTEM_PYTHON} is not installed"
    probe = subprocess.run(
        [str(SYSTEM_PYTHON), "-c", "import tf.transformations, tf2_ros, rospy"],
        capture_output=True,
        check=False,
    )
    if probe.returncode != 0:
        return "Debian's tf/tf2_ros (python3-tf, python3-tf2-ros) are not installed"
    return None


class TfOracle:
    """One long-lived oracle process."""

    def __init__(self) -> None:
        self.proc = subprocess.Popen(
            [str(SYSTEM_PYTHON), str(SCRIPT), "--serve"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,  # tf2's console warnings
            text=True,
            env={"PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"},
        )

    def ask(self, request: dict[str, Any]) -> dict[str, Any]:
        assert self.proc.stdin is not None
        assert self.proc.stdout is not None
        self.proc.stdin.write(json.dumps(request) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            msg = "the tf oracle died"
            raise RuntimeError(msg)
        answer: dict[str, Any] = json.loads(line)
        return answer

    def close(self) -> None:
        if self.proc.stdin is not None:
            self.proc.stdin.close()
        self.proc.wait(timeout=30)


def oracle_fixture() -> Iterator[TfOracle]:
    why = missing()
    if why is not None:
        pytest.skip(why)
    oracle = TfOracle()
    try:
        yield oracle
    finally:
        oracle.close()


def check_steps(
    oracle: TfOracle,
    kind: str,
    scenario: dict[str, Any],
    ours: Callable[[dict[str, Any]], list[Any]],
) -> None:
    """The oracle's run of ``scenario`` against ``ours(scenario)``, step by step; ``kind``
    is the request's key, which names the API the oracle runs it through."""
    (theirs,) = oracle.ask({kind: [scenario]})[kind]
    for step, a, b in zip(scenario["steps"], ours(scenario), theirs, strict=True):
        assert same(a, b, 1e-9), f"{step}:\n ours   {a}\n theirs {b}"


def encode(value: Any) -> Any:
    """As the oracle encodes its results (arrays, tuples, lists and numbers kept apart)."""
    if isinstance(value, np.ndarray):
        return {"ndarray": encode(value.tolist()), "dtype": value.dtype.kind}
    if isinstance(value, tuple):
        return {"tuple": [encode(v) for v in value]}
    if isinstance(value, list):
        return [encode(v) for v in value]
    if isinstance(value, bool | np.bool_):
        return {"bool": bool(value)}
    if isinstance(value, float | np.floating):
        v = float(value)
        return v if math.isfinite(v) else {"float": repr(v)}
    if isinstance(value, int | np.integer):
        return {"int": int(value)}
    if hasattr(value, "secs") and hasattr(value, "nsecs") and hasattr(value, "now"):
        return {"time": [value.secs, value.nsecs]}
    if value is None or isinstance(value, str):
        return value
    return {"repr": repr(value)}


def same(ours: Any, theirs: Any, tol: float = 1e-12) -> bool:
    """Equal encodings, numbers to within ``tol`` (absolute, or relative for large ones)."""
    if isinstance(ours, float) and isinstance(theirs, float):
        return abs(ours - theirs) <= tol * max(1.0, abs(theirs))
    if isinstance(ours, list) and isinstance(theirs, list):
        return len(ours) == len(theirs) and all(
            same(a, b, tol) for a, b in zip(ours, theirs, strict=True)
        )
    if isinstance(ours, dict) and isinstance(theirs, dict):
        return ours.keys() == theirs.keys() and all(same(ours[k], theirs[k], tol) for k in ours)
    return bool(ours == theirs)
