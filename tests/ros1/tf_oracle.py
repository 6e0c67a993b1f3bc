"""Run by Debian's /usr/bin/python3 (which has tf, tf2_ros and rospy): reads a JSON request on
stdin, answers JSON on stdout. Not imported by the tests themselves.

One request on stdin, or with ``--serve`` one per line (so hypothesis can ask example by
example). Requests:

- ``{"transformations": [[name, args, kwargs], ...]}``: calls of ``tf.transformations``;
- ``{"scenarios": [{"cache_time": s, "transforms": [...], "queries": [...]}, ...]}``: a
  fresh ``tf2_ros.Buffer`` (no node needed) filled with transforms, then queried
  (``tests/ros1/tf_scenarios.py`` describes the encoding);
- ``{"tf1": [...]}``: the same for ``tf.Transformer``.

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


def time(value: Any) -> rospy.Time:
    return rospy.Time(value[0], value[1])


def duration(value: Any) -> rospy.Duration:
    return rospy.Duration(value[0], value[1])


def transform_stamped(spec: dict[str, Any]) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id = spec["parent"]
    t.child_frame_id = spec["child"]
    t.header.stamp = time(spec["stamp"])
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = spec["t"]
    r = t.transform.rotation
    r.x, r.y, r.z, r.w = spec["q"]
    return t


def encode_transform(t: TransformStamped) -> Any:
    tr, r = t.transform.translation, t.transform.rotation
    return {
        "parent": t.header.frame_id,
        "child": t.child_frame_id,
        "stamp": [t.header.stamp.secs, t.header.stamp.nsecs],
        "t": [tr.x, tr.y, tr.z],
        "q": [r.x, r.y, r.z, r.w],
    }


def fill(target: Any, transforms: list[dict[str, Any]], tf1: bool) -> None:
    for spec in transforms:
        msg = transform_stamped(spec)
        authority = spec.get("authority", "default_authority")
        if tf1:
            target.setTransform(msg, authority)
        elif spec.get("static"):
            target.set_transform_static(msg, authority)
        else:
            target.set_transform(msg, authority)


def query(target: Any, q: list[Any]) -> Any:
    name, args = q[0], q[1:]
    converted = []
    for a in args:
        if isinstance(a, dict) and "time" in a:
            converted.append(time(a["time"]))
        elif isinstance(a, dict) and "duration" in a:
            converted.append(duration(a["duration"]))
        else:
            converted.append(a)
    try:
        result = getattr(target, name)(*converted)
    except Exception as err:  # noqa: BLE001 (reports whatever tf2 raises)
        return error(err)
    if isinstance(result, TransformStamped):
        return {"transform": encode_transform(result)}
    return encode(result)


def run_scenarios(scenarios: list[Any], tf1: bool) -> list[Any]:
    out = []
    for s in scenarios:
        cache = s.get("cache_time")
        if tf1:
            target: Any = tf.Transformer(True, None if cache is None else rospy.Duration(cache))
            target.setUsingDedicatedThread(True)
        else:
            target = tf2_ros.Buffer(None if cache is None else rospy.Duration(cache), debug=False)
        fill(target, s["transforms"], tf1)
        out.append([query(target, q) for q in s["queries"]])
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
