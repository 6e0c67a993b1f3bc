"""Run by Debian's /usr/bin/python3 (which has genpy and generated message modules): reads a
JSON request on stdin, answers JSON on stdout. Not imported by the tests themselves."""

import importlib
import io
import json
import pkgutil
import sys
from typing import Any

PACKAGES = (
    "actionlib",
    "actionlib_msgs",
    "geometry_msgs",
    "move_base_msgs",
    "nav_msgs",
    "rosgraph_msgs",
    "sensor_msgs",
    "std_msgs",
    "std_srvs",
    "tf2_msgs",
    "trajectory_msgs",
    "visualization_msgs",
    "diagnostic_msgs",
)


def available() -> dict[str, Any]:
    found: dict[str, Any] = {}
    for pkg in PACKAGES:
        for kind in ("msg", "srv"):
            try:
                module = importlib.import_module(f"{pkg}.{kind}")
            except ImportError:
                continue
            for info in pkgutil.iter_modules(module.__path__):
                if info.name.startswith("_"):
                    name = info.name[1:]
                    found[f"{pkg}/{kind}/{name}"] = getattr(module, name)
    return found


def serialized(msg: Any) -> str:
    buff = io.BytesIO()
    msg.serialize(buff)
    return buff.getvalue().hex()


def describe(cls: Any) -> dict[str, Any]:
    msg = cls()
    full_text = cls._full_text
    return {
        "type": cls._type,
        "md5sum": cls._md5sum,
        "slots": list(cls.__slots__),
        "slot_types": list(cls._slot_types),
        "has_header": cls._has_header,
        "str": str(msg),
        "bytes": serialized(msg),
        "deps": [line[5:] for line in full_text.splitlines() if line.startswith("MSG: ")],
    }


def run_errors(classes: dict[str, Any], cases: list[dict[str, Any]]) -> list[Any]:
    out: list[Any] = []
    for case in cases:
        cls = classes[case["type"]]
        try:
            msg = cls(*case.get("args", []), **case.get("kwargs", {}))
            for name, value in case.get("set", {}).items():
                setattr(msg, name, value)
            if case.get("serialize"):
                serialized(msg)
            elif case.get("deserialize") is not None:
                cls().deserialize(bytes.fromhex(case["deserialize"]))
            out.append(None)
        except Exception as err:  # noqa: BLE001 (reports whatever genpy raises)
            out.append([type(err).__name__, str(err)])
    return out


def main() -> None:
    request = json.load(sys.stdin)
    found = available()
    answer: dict[str, Any] = {"types": {}, "services": {}, "filled": {}, "errors": []}
    for full, cls in found.items():
        if "/srv/" in full:
            answer["services"][full] = {
                "type": cls._type,
                "md5sum": cls._md5sum,
                "request": describe(cls._request_class),
                "response": describe(cls._response_class),
            }
        else:
            answer["types"][full] = describe(cls)
    for full, data in request.get("filled", {}).items():
        cls = found.get(full)
        if cls is None:
            pkg, _, name = full.split("/")
            base = name.replace("_Request", "").replace("_Response", "")
            service = found.get(f"{pkg}/srv/{base}")
            if service is None:
                continue
            cls = service._request_class if name.endswith("_Request") else service._response_class
        msg = cls().deserialize(bytes.fromhex(data))
        answer["filled"][full] = {"str": str(msg), "bytes": serialized(msg)}
    classes = {cls._type: cls for cls in found.values() if hasattr(cls, "__slots__")}
    answer["errors"] = run_errors(classes, request.get("errors", []))
    json.dump(answer, sys.stdout)


main()
