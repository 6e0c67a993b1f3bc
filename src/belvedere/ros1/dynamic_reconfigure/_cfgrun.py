"""Runs one ``.cfg`` generator script in a process of its own and prints what it generates as
JSON. Started by :mod:`._cfgfile` (which has checked the script's syntax tree first) with
``python -I -S``: the standard library only, a memory cap, builtins cut to pure computation,
and in place of ROS's generator a recorder of its calls that writes no file.

Prints ``{"generated": {...}}`` or ``{"error": message, "line": n}``.
"""

from __future__ import annotations

import builtins
import json
import math
import resource
import sys
import traceback
import types
from typing import Any

_MEMORY = 512 << 20
_SAFE = [
    "abs",
    "all",
    "any",
    "bool",
    "dict",
    "enumerate",
    "float",
    "int",
    "len",
    "list",
    "max",
    "min",
    "range",
    "reversed",
    "round",
    "set",
    "sorted",
    "str",
    "sum",
    "tuple",
    "zip",
    "isinstance",
    "repr",
    "ValueError",
    "TypeError",
    "Exception",
]


def _say(text: str) -> None:
    sys.stdout.write(text + "\n")


class CfgAbortError(Exception):
    """The script's own mistake, reported at its line."""


def _line() -> int:
    """The ``.cfg``'s line that called the generator."""
    frame = sys._getframe(1)
    while frame.f_back is not None and frame.f_code.co_filename != sys.argv[1]:
        frame = frame.f_back
    return frame.f_lineno if frame.f_code.co_filename == sys.argv[1] else 0


class _Group:
    def __init__(
        self, gen: ParameterGenerator, name: Any, kind: Any, state: Any, ident: int, parent: int
    ) -> None:
        self.gen = gen
        self.name = str(name).replace(" ", "_")
        self.type, self.state, self.id, self.parent = kind, state, ident, parent
        self.params: list[dict[str, Any]] = []
        self.groups: list[_Group] = []

    def add(
        self,
        name: Any,
        paramtype: Any,
        level: Any,
        description: Any,
        default: Any = None,
        min: Any = None,
        max: Any = None,
        edit_method: Any = "",
    ) -> None:
        self.params.append(
            {
                "name": name,
                "type": paramtype,
                "level": level,
                "description": description,
                "default": default,
                "min": min,
                "max": max,
                "edit_method": edit_method,
                "line": _line(),
            }
        )

    def add_group(self, name: Any, type: Any = "", state: Any = True) -> _Group:
        group = _Group(self.gen, name, type, state, self.gen.next_id, self.id)
        self.gen.next_id += 1
        self.groups.append(group)
        return group

    def data(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "type": self.type,
            "state": self.state,
            "id": self.id,
            "parent": self.parent,
            "params": self.params,
            "groups": [g.data() for g in self.groups],
        }


class ParameterGenerator:
    """Records what a ``.cfg`` asks ROS's generator for."""

    def __init__(self) -> None:
        self.next_id = 1
        self.group = _Group(self, "Default", "", True, 0, 0)
        self.constants: list[dict[str, Any]] = []

    def add(self, *args: Any, **kwargs: Any) -> None:
        self.group.add(*args, **kwargs)

    def add_group(self, name: Any, type: Any = "", state: Any = True) -> _Group:
        return self.group.add_group(name, type, state)

    def const(self, name: Any, type: Any, value: Any, descr: Any) -> dict[str, Any]:
        const = {"name": name, "type": type, "value": value, "description": descr}
        const["srcline"] = _line()
        self.constants.append(const)
        return const

    def enum(self, constants: Any, description: Any) -> str:
        if len({c["type"] for c in constants}) != 1:
            msg = "the enum's constants are of different types"
            raise CfgAbortError(msg)
        return repr({"enum": constants, "enum_description": description})

    def generate(self, pkgname: Any, nodename: Any, name: Any) -> int:
        _GENERATED.append(
            {
                "package": pkgname,
                "node": nodename,
                "name": name,
                "root": self.group.data(),
                "constants": self.constants,
            }
        )
        return 0


_GENERATED: list[dict[str, Any]] = []


def _module(name: str, **values: Any) -> types.ModuleType:
    module = types.ModuleType(name)
    module.__dict__.update(values)
    return module


def _run(path: str) -> dict[str, Any]:
    with open(path, "rb") as f:
        code = compile(f.read(), path, "exec", dont_inherit=True)
    generator = _module(
        "dynamic_reconfigure.parameter_generator_catkin",
        ParameterGenerator=ParameterGenerator,
        str_t="str",
        bool_t="bool",
        int_t="int",
        double_t="double",
    )
    package = _module(
        "dynamic_reconfigure",
        parameter_generator_catkin=generator,
        parameter_generator=generator,
    )
    allowed = {
        "dynamic_reconfigure": package,
        "dynamic_reconfigure.parameter_generator_catkin": generator,
        "dynamic_reconfigure.parameter_generator": generator,
        "roslib": _module("roslib", load_manifest=lambda name: None),
        "math": math,
    }

    def importer(name: str, *args: Any, fromlist: Any = (), level: int = 0) -> Any:
        if name not in allowed:
            msg = f"a .cfg may not import {name}"
            raise CfgAbortError(msg)
        fromlist = args[2] if len(args) > 2 else fromlist
        return allowed[name] if fromlist or "." not in name else allowed[name.split(".")[0]]

    def stop(code: Any = 0) -> None:
        raise SystemExit(code)

    safe: dict[str, Any] = {name: getattr(builtins, name) for name in _SAFE}
    safe.update(__import__=importer, exit=stop, quit=stop, print=lambda *a, **k: None)
    scope = {"__builtins__": safe, "__name__": "__main__", "__file__": path}
    try:
        exec(code, scope)
    except SystemExit:
        pass
    except BaseException as err:  # noqa: BLE001 (the script's error, reported at its line)
        line = 0
        for frame, lineno in traceback.walk_tb(err.__traceback__):
            if frame.f_code.co_filename == path:
                line = lineno
        text = str(err) if isinstance(err, CfgAbortError) else f"{type(err).__name__}: {err}"
        return {"error": text, "line": line}
    if not _GENERATED:
        return {"error": "it never calls gen.generate(PACKAGE, node, name)", "line": 0}
    return {"generated": _GENERATED[-1]}


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (_MEMORY, _MEMORY))
    _say(json.dumps(_run(sys.argv[1]), default=repr))


if __name__ == "__main__":
    main()
