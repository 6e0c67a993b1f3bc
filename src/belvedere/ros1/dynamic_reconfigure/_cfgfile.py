"""``.cfg`` files — dynamic_reconfigure's generator scripts — read without trusting them.

A ``.cfg`` is Python that ROS runs at build time. Here its syntax tree is checked first (it may
import only the generator, ``roslib`` and ``math``; no name or attribute with a leading
underscore, which is how sandboxes are escaped), then it runs in a process of its own
(:mod:`._cfgrun`) bounded in time, output and memory, with builtins cut to computation: no
file, no network, no import beyond those. What it generated comes back as data and becomes a
:class:`Description`; every error names the ``.cfg`` line.
"""

from __future__ import annotations

import ast
import json
import sys
from functools import cache
from pathlib import Path
from typing import Any, Final

from belvedere.bounded import LimitError, read_regular_text, run_bounded
from belvedere.errors import ParseError, SourceLocation
from belvedere.ros1.dynamic_reconfigure._description import (
    TYPES,
    Description,
    Group,
    Param,
    ReconfigureError,
    typed,
)

__all__ = ["CfgError", "load_cfg"]

_RUNNER: Final = Path(__file__).with_name("_cfgrun.py")
_IMPORTS: Final = frozenset(
    {
        "dynamic_reconfigure",
        "dynamic_reconfigure.parameter_generator_catkin",
        "dynamic_reconfigure.parameter_generator",
        "roslib",
        "math",
    }
)
_CFG_BYTES: Final = 1 << 20
_SECONDS: Final = 10.0
_OUTPUT_BYTES: Final = 16 << 20


class CfgError(ParseError):
    """A ``.cfg`` that cannot be run safely, or whose parameters dynamic_reconfigure refuses."""


def _check(tree: ast.AST, path: str) -> None:
    for node in ast.walk(tree):
        where = SourceLocation(
            path, getattr(node, "lineno", 0), getattr(node, "col_offset", -1) + 1
        )
        names: list[str] = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            names = [("." * node.level) + (node.module or "")]
        for name in names:
            if name not in _IMPORTS:
                msg = f"a .cfg may not import {name}"
                hint = "it runs sandboxed: only dynamic_reconfigure's generator, roslib and math"
                raise CfgError(msg, where, hint=hint)
        bad = (
            node.attr
            if isinstance(node, ast.Attribute)
            else node.id
            if isinstance(node, ast.Name)
            else None
        )
        if bad is not None and bad.startswith("_"):
            msg = f"a .cfg may not use the name {bad!r} (a leading underscore)"
            raise CfgError(msg, where, hint="it runs sandboxed: only the generator's API")
        if isinstance(node, ast.Global | ast.Nonlocal | ast.AsyncFunctionDef | ast.Await):
            msg = "a .cfg may not use global, nonlocal or async code"
            raise CfgError(msg, where)


def _param(data: dict[str, Any], path: str) -> Param:
    where = SourceLocation(path, int(data.get("line", 0)))
    try:
        return Param.make(
            data["name"],
            data["type"],
            data["level"],
            data["description"],
            data["default"],
            data["min"],
            data["max"],
            data["edit_method"],
        )
    except ReconfigureError as err:
        raise CfgError(err.message, where, hint=err.hint) from None
    except (TypeError, KeyError):
        msg = "gen.add(name, type, level, description, ...) is malformed"
        raise CfgError(msg, where) from None


def _group(data: dict[str, Any], path: str) -> Group:
    return Group(
        str(data["name"]),
        str(data["type"]),
        bool(data["state"]),
        int(data["id"]),
        int(data["parent"]),
        [_param(p, path) for p in data["params"]],
        [_group(g, path) for g in data["groups"]],
    )


def _constant(const: Any, path: str) -> tuple[str, Any]:
    if not isinstance(const, dict) or not isinstance(const.get("name"), str):
        msg = "gen.const(name, type, value, description) is malformed"
        raise CfgError(msg, SourceLocation(path))
    where = SourceLocation(path, int(const.get("srcline", 0)))
    name, kind = const["name"], const.get("type")
    if kind not in TYPES:
        msg = f"constant {name!r}: unknown type {kind!r}"
        raise CfgError(msg, where, hint="one of int_t, double_t, str_t, bool_t")
    try:
        return name, typed(name, kind, const.get("value"))
    except ReconfigureError as err:
        raise CfgError(err.message.replace("parameter", "constant", 1), where) from None


@cache
def _load(path: str, mtime_ns: int) -> Description:
    text = read_regular_text(Path(path), what=".cfg file", limit=_CFG_BYTES)
    try:
        tree = ast.parse(text, path)
    except SyntaxError as err:
        where = SourceLocation(path, err.lineno or 0, err.offset or 0)
        msg = f"invalid Python: {err.msg}"
        raise CfgError(msg, where) from None
    _check(tree, path)
    ran = run_bounded(
        [sys.executable, "-I", "-S", str(_RUNNER), path], seconds=_SECONDS, limit=_OUTPUT_BYTES
    )
    if ran.stopped:
        reason = "ran too long" if ran.stopped == "time" else "printed too much"
        msg = f"the generator script {reason}"
        raise CfgError(msg, SourceLocation(path))
    try:
        out = json.loads(ran.stdout)
    except ValueError:
        detail = ran.stderr.decode(errors="replace").strip().splitlines()[-1:] or ["nothing"]
        msg = f"the generator script failed: {detail[0]}"
        raise CfgError(msg, SourceLocation(path)) from None
    if "error" in out:
        raise CfgError(out["error"], SourceLocation(path, int(out["line"])))
    gen = out["generated"]
    root = _group(gen["root"], path)
    constants = dict(_constant(c, path) for c in gen["constants"])
    try:
        return Description(str(gen["name"]), root, constants)
    except ReconfigureError as err:
        raise CfgError(err.message, SourceLocation(path), hint=err.hint) from None


def load_cfg(path: Path) -> Description:
    """The description a ``.cfg`` generates (cached while the file is unchanged).

    Raises:
        CfgError: it is not a .cfg the sandbox runs, or its parameters are malformed.
        LimitError: it is not a readable regular file of a sane size.
    """
    try:
        stat = path.stat()
    except OSError as err:
        msg = f"cannot read {path}: {err.strerror}"
        raise LimitError(msg) from None
    return _load(str(path), stat.st_mtime_ns)
