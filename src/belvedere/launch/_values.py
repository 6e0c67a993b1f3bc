"""A ``<param>``'s value: typed as roslaunch types it (``type=`` or its guess), or printed by
a command (xacro in process, any other program as a bounded subprocess: see
:func:`run_program`)."""

from __future__ import annotations

import math
import shlex
import sys
from typing import Any

from belvedere import bounded
from belvedere.bounded import describe_size
from belvedere.description.xacro._command import is_xacro_program, parse_xacro_argv
from belvedere.description.xacro._run import run_command
from belvedere.errors import ParseError, SourceLocation
from belvedere.launch._model import LaunchError, LaunchFile
from belvedere.packages import PackageIndex
from belvedere.yamlfile import load_yaml

__all__ = ["finite", "param_bool", "param_command", "run_program", "typed_value"]


def param_command(
    command: str, at: SourceLocation | None, packages: PackageIndex, files: list[LaunchFile]
) -> str:
    """A ``<param command>``: xacro runs here, in process; anything else as a program."""
    try:
        words = shlex.split(command)
    except ValueError as err:
        msg = f"cannot split command {command!r}: {err}"
        raise LaunchError(msg, at) from None
    if not words:
        msg = "empty command"
        raise LaunchError(msg, at)
    if is_xacro_program(words[0]):
        try:
            cmd = parse_xacro_argv(words[1:])
            result = run_command(cmd, packages=packages)
        except ParseError as err:
            if at is not None:
                err.add_trail("in the <param command> at", at)
            raise
        files.extend(
            LaunchFile("yaml" if f.endswith((".yaml", ".yml")) else "xacro", f)
            for f in result.files
        )
        return result.text or ""
    return run_program(words, command, at)


def run_program(words: list[str], command: str, at: SourceLocation | None) -> str:
    """What a program prints on stdout, decoded as roslaunch decodes it (strict UTF-8).

    The program reads no input (stdin is ``/dev/null``) and is bounded: its stdout and its
    stderr are read as they come, at most :data:`~belvedere.bounded.COMMAND_OUTPUT_BYTES`
    each, and it may run :data:`~belvedere.bounded.COMMAND_SECONDS`; past either it is
    killed (with whatever it started: it runs in a process group of its own) and the
    ``<param>`` is an error at ``at``.

    Raises:
        LaunchError: it cannot start, fails, runs or prints too long, or prints bytes that
            are not UTF-8 (roslaunch fails on them too).
    """
    limit, seconds = bounded.COMMAND_OUTPUT_BYTES, bounded.COMMAND_SECONDS
    try:
        ran = bounded.run_bounded(words, seconds=seconds, limit=limit)
    except OSError as err:
        msg = f"command {command!r} could not run: {err}"
        raise LaunchError(msg, at) from None
    if ran.stopped == "time":
        msg = f"command {command!r} did not end within {seconds:g} s: stopped"
        raise LaunchError(msg, at)
    if ran.stopped:
        msg = (
            f"command {command!r} printed more than {describe_size(limit)} on {ran.stopped}: "
            "stopped (belvedere keeps at most that much of a command's output)"
        )
        raise LaunchError(msg, at)
    if ran.status != 0:
        status = ran.status or 0
        how = f"exit {status}" if status > 0 else f"killed by signal {-status}"
        msg = f"command {command!r} failed ({how}): {_tail(ran.stderr)}"
        raise LaunchError(msg, at)
    out = ran.stdout
    try:
        return out.decode("utf-8")
    except UnicodeDecodeError as bad:
        msg = (
            f"command {command!r} printed bytes that are not UTF-8 (0x{out[bad.start]:02x} "
            f"at byte {bad.start}); roslaunch refuses them too"
        )
        raise LaunchError(msg, at) from None


def _tail(stderr: bytes, most: int = 2000) -> str:
    """The end of what a failed command wrote on stderr, for its error message."""
    text = stderr.decode("utf-8", errors="replace").strip()
    return text if len(text) <= most else "…" + text[-most:]


def param_bool(value: str, what: str, at: SourceLocation | None) -> bool:
    """A launch boolean, as roslaunch reads one: true, false, 1 or 0 (any case)."""
    low = value.strip().lower()
    if low in ("true", "1"):
        return True
    if low in ("false", "0"):
        return False
    msg = f"{what}: expected true, false, 1 or 0"
    raise LaunchError(msg, at)


def typed_value(raw: str, kind: str, at: SourceLocation | None) -> Any:
    """A ``<param>`` value of ``type`` ``kind`` (``auto`` guesses as roslaunch does)."""
    try:
        if kind == "str" or kind == "string":
            return raw
        if kind == "int":
            return int(raw.strip())
        if kind == "double":
            return finite(float(raw.strip()), raw, at)
        if kind in ("bool", "boolean"):
            return param_bool(raw, f"bool value {raw!r}", at)
        if kind == "yaml":
            return load_yaml(raw, path=str(at.path) if at else "<param>").data
    except ValueError:
        msg = f"param value {raw!r} is not a valid {kind}"
        raise LaunchError(msg, at) from None
    if kind != "auto":
        msg = f"unknown param type {kind!r} (str, int, double, bool, yaml, auto)"
        raise LaunchError(msg, at)
    # roslaunch's guess: a '.' means a double, else an int (but "1_000" stays text: Python
    # would read it as 1000), then true/false in any case, else the text itself
    try:
        if "." in raw:
            return finite(float(raw), raw, at)
        if "_" not in raw:
            return int(raw)
    except ValueError:
        pass
    if raw.lower() in ("true", "false"):
        return raw.lower() == "true"
    return raw


def finite(value: float, raw: str, at: SourceLocation | None) -> float:
    """roslaunch would pass ``nan``/``inf``/``1e309`` on as a float; we refuse it here, where
    the line is known, rather than let a node meet it."""
    if not math.isfinite(value):
        msg = f"param value {raw!r} is not a finite number"
        hint = f'the largest double is ±{sys.float_info.max:.17g}; for text, add type="str"'
        raise LaunchError(msg, at, hint=hint)
    return value


def test_limits(
    time_limit: str | None, retry: str | None, at: SourceLocation | None
) -> tuple[float, int]:
    """A ``<test>``'s ``time-limit`` (seconds, positive; 60 when not given) and ``retry``
    (a whole number; 0), checked as roslaunch checks them."""
    limit = 60.0
    if time_limit:
        try:
            limit = float(time_limit)
        except ValueError:
            msg = f"'time-limit' must be a number: [{time_limit}]"
            raise LaunchError(msg, at) from None
        if not limit > 0.0 or not math.isfinite(limit):
            msg = f"'time-limit' must be a positive number: [{time_limit}]"
            raise LaunchError(msg, at)
    count = 0
    if retry:
        try:
            count = int(retry)
        except ValueError:
            msg = f"'retry' must be a number: [{retry}]"
            raise LaunchError(msg, at) from None
    return limit, count
