"""Run by Debian's /usr/bin/python3 (which has tf, tf2_ros and rospy): reads a JSON request on
stdin, answers JSON on stdout. Not imported by the tests themselves.

One request on stdin, or with ``--serve`` one per line (so hypothesis can ask example by
example). Requests:

- ``{"transformations": [[name, args, kwargs], ...]}``: calls of ``tf.transformations``;
- ``{"scenarios": [{"cache_time": [secs, nsecs] | None, "steps": [[method, *args]]}]}``: a
  fresh ``tf2_ros.Buffer`` (no node needed), its methods called in turn
  (``tests/ros1/tf_scenarios.py`` describes the encoding);
- ``{"tf1": [...]}``: the same for a ``tf.TransformerROS``.

Values are encoded so arrays, tuples and lists stay distinct (see :func:`encode`).
"""

import importlib
import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy

# The steps are run as belvedere's side runs them: its module, from this checkout.
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from tests.ros1.tf_steps import Steps, error

# Debian's modules, imported by name (mypy checks this file without them)
rospy: Any = importlib.import_module("rospy")
tf: Any = importlib.import_module("tf")
tf2_ros: Any = importlib.import_module("tf2_ros")
transformations: Any = importlib.import_module("tf.transformations")
TransformStamped: Any = importlib.import_module("geometry_msgs.msg").TransformStamped


def encode(value: Any) -> Any:
    if isinstance(value, numpy.ndarray):
        return {"ndarray": encode(value.tolist()), "dtype": value.dtype.kind}
    if isinstance(value, tuple):
        return {"tuple": [encode(v) for v in value]}
    if isinstance(value, list):
        return [encode(v) for v in value]
    if isinstance(value, (bool, numpy.bool_)):
        return {"bool": bool(value)}
    if isinstance(value, (float, numpy.floating)):
        v = float(value)
        return v if math.isfinite(v) else {"float": repr(v)}
    if isinstance(value, (int, numpy.integer)):
        return {"int": int(value)}
    if isinstance(value, rospy.Time):
        return {"time": [value.secs, value.nsecs]}
    if value is None or isinstance(value, str):
        return value
    return {"repr": repr(value)}


def decode(value: Any) -> Any:
    """JSON arguments back to Python: ``{"tuple": [...]}`` is a tuple."""
    if isinstance(value, dict) and "tuple" in value:
        return tuple(decode(v) for v in value["tuple"])
    if isinstance(value, list):
        return [decode(v) for v in value]
    return value


def run_transformations(calls: list[Any]) -> list[Any]:
    out: list[Any] = []
    for name, args, kwargs in calls:
        try:
            result = getattr(transformations, name)(
                *decode(args), **{k: decode(v) for k, v in kwargs.items()}
            )
            out.append(encode(result))
        except Exception as err:  # noqa: BLE001 (reports whatever tf raises)
            out.append(error(err))
    return out


def _message_class(name: str) -> Any:
    pkg, type_name = name.split("/")
    return getattr(importlib.import_module(f"{pkg}.msg"), type_name)


STEPS = Steps(rospy, _message_class, encode)


def run_scenarios(scenarios: list[Any], tf1: bool) -> list[Any]:
    out = []
    for s in scenarios:
        cache = s.get("cache_time")
        cache_time = None if cache is None else rospy.Duration(*cache)
        if tf1:
            target: Any = tf.TransformerROS(True, cache_time)
            target.setUsingDedicatedThread(True)
        else:
            target = tf2_ros.Buffer(cache_time, debug=False)
        out.append(STEPS.run(target, s["steps"]))
    return out


def handle(request: dict[str, Any]) -> dict[str, Any]:
    return {
        "transformations": run_transformations(request.get("transformations", [])),
        "scenarios": run_scenarios(request.get("scenarios", []), tf1=False),
        "tf1": run_scenarios(request.get("tf1", []), tf1=True),
        "axes": {k: list(v) for k, v in transformations._AXES2TUPLE.items()},
    }


def main() -> None:
    """One request on stdin, or (``--serve``) one request per line, each answered by a line."""
    if "--serve" not in sys.argv:
        json.dump(handle(json.load(sys.stdin)), sys.stdout)
        return
    for line in sys.stdin:
        sys.stdout.write(json.dumps(handle(json.loads(line))) + "\n")
        sys.stdout.flush()


main()
