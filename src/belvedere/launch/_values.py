"""A ``<param>``'s value: typed as roslaunch types it (``type=`` or its guess), or printed by
a command (xacro in process, any other program as a bounded subprocess: see
:func:`run_program`)."""

from __future__ import annotations

import contextlib
import math
import os
import selectors
import shlex
import signal
import subprocess
import sys
import time
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
        process = subprocess.Popen(
            words,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            start_new_session=True,
        )
    except OSError as err:
        msg = f"command {command!r} could not run: {err}"
        raise LaunchError(msg, at) from None
    try:
        out, err_text, problem = _collect(process, limit, time.monotonic() + seconds)
    finally:
        _kill(process)
    if problem == "time":
        msg = f"command {command!r} did not end within {seconds:g} s: stopped"
        raise LaunchError(msg, at)
    if problem:
        msg = (
            f"command {command!r} printed more than {describe_size(limit)} on {problem}: "
            "stopped (belvedere keeps at most that much of a command's output)"
        )
        raise LaunchError(msg, at)
    status = process.returncode
    if status != 0:
        how = f"exit {status}" if status > 0 else f"killed by signal {-status}"
        msg = f"command {command!r} failed ({how}): {_tail(err_text)}"
        raise LaunchError(msg, at)
    try:
        return out.decode("utf-8")
    except UnicodeDecodeError as bad:
        msg = (
            f"command {command!r} printed bytes that are not UTF-8 (0x{out[bad.start]:02x} "
            f"at byte {bad.start}); roslaunch refuses them too"
        )
        raise LaunchError(msg, at) from None


def _collect(
    process: subprocess.Popen[bytes], limit: int, deadline: float
) -> tuple[bytes, bytes, str]:
    """(stdout, stderr, what went wrong: ``""``, ``"time"``, ``"stdout"`` or ``"stderr"``),
    reading both pipes as they fill until both close and the program ends."""
    assert process.stdout is not None
    assert process.stderr is not None
    streams = {
        process.stdout.fileno(): ("stdout", bytearray()),
        process.stderr.fileno(): ("stderr", bytearray()),
    }
    with selectors.DefaultSelector() as selector:
        for fd in streams:
            selector.register(fd, selectors.EVENT_READ)
        while selector.get_map():
            left = deadline - time.monotonic()
            if left <= 0:
                return b"", b"", "time"
            for key, _ in selector.select(left):
                chunk = os.read(key.fd, 1 << 16)
                name, got = streams[key.fd]
                if not chunk:
                    selector.unregister(key.fd)
                    continue
                got += chunk
                if len(got) > limit:
                    return b"", b"", name
    try:
        process.wait(max(0.0, deadline - time.monotonic()))
    except subprocess.TimeoutExpired:
        return b"", b"", "time"
    out, err = (bytes(got) for _, got in streams.values())
    return out, err, ""


def _kill(process: subprocess.Popen[bytes]) -> None:
    """End the program and what it started (its process group), if still there; close its
    pipes."""
    if process.returncode is None:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    for pipe in (process.stdout, process.stderr):
        if pipe is not None:
            pipe.close()


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
