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
from typing import Any

import numpy

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


def error(err: BaseException) -> dict[str, Any]:
    return {"error": [type(err).__name__, str(err)]}


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


def message(spec: dict[str, Any]) -> Any:
    """``{"msg": "pkg/Type", "fields": {...}}`` as a message of Debian's classes."""
    pkg, name = spec["msg"].split("/")
    msg = getattr(importlib.import_module(f"{pkg}.msg"), name)()
    for field, value in spec["fields"].items():
        setattr(msg, field, argument(value))
    return msg


def argument(value: Any) -> Any:
    """A step's argument: times, durations and messages are tagged dictionaries."""
    if isinstance(value, dict) and "time" in value:
        return rospy.Time(*value["time"])
    if isinstance(value, dict) and "duration" in value:
        return rospy.Duration(*value["duration"])
    if isinstance(value, dict) and "msg" in value:
        return message(value)
    if isinstance(value, list):
        return [argument(v) for v in value]
    return value


def result(value: Any) -> Any:
    """A step's result; messages field by field, times as [secs, nsecs]."""
    if hasattr(value, "_type") and hasattr(value, "__slots__"):
        return {
            "msg": value._type,
            "fields": {s: result(getattr(value, s)) for s in value.__slots__},
        }
    if hasattr(value, "secs") and hasattr(value, "nsecs"):
        return {"time": [value.secs, value.nsecs]}
    if isinstance(value, (list, tuple)) and not isinstance(value, str):
        items = [result(v) for v in value]
        return items if isinstance(value, list) else {"tuple": items}
    return encode(value)


def run_steps(target: Any, steps: list[Any]) -> list[Any]:
    out = []
    for name, *args in steps:
        try:
            out.append(result(getattr(target, name)(*[argument(a) for a in args])))
        except Exception as err:  # noqa: BLE001 (reports whatever tf raises)
            out.append(error(err))
    return out


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
        out.append(run_steps(target, s["steps"]))
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
