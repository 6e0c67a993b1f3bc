"""rospy's log functions: ROS's console format and streams, ``/rosout``, and the
``_throttle``/``_throttle_identical``/``_once`` variants (each per call site)."""

from __future__ import annotations

import sys
import time
from typing import Any

from belvedere.graph._log import (
    DEBUG,
    ERROR,
    FATAL,
    INFO,
    WARN,
    console_line,
    log_message,
    write_console,
)
from belvedere.ros1.rospy import _state

__all__ = [
    "DEBUG",
    "ERROR",
    "FATAL",
    "INFO",
    "WARN",
    "log",
    "log_once",
    "log_throttle",
    "log_throttle_identical",
    "publish_rosout",
]

_last: dict[tuple[str, int], tuple[int, str]] = {}
_once: set[tuple[str, int]] = set()


def _site(depth: int) -> tuple[str, int, str]:
    frame = sys._getframe(depth + 1)
    return frame.f_code.co_filename, frame.f_lineno, frame.f_code.co_name


def _text(msg: Any, args: tuple[Any, ...]) -> str:
    text = str(msg)
    if args:
        text = text % args
    return text


def _console(level: int, text: str) -> str:
    runtime = _state.current()
    sim_ns = runtime.now_ns() if runtime is not None and runtime.sim_time else None
    return console_line(level, text, node=_state.caller_id(), sim_ns=sim_ns)


def log(level: int, msg: Any, args: tuple[Any, ...], *, depth: int = 1) -> None:
    """Print (by the node's level) and publish on ``/rosout`` one message."""
    text = _text(msg, args)
    runtime = _state.current()
    if runtime is None:
        # Before init_node rospy's loggers have no handler: Python prints warnings and worse
        # bare on stderr, and drops the rest.
        if level >= WARN:
            sys.stderr.write(text + "\n")
        return
    if level < runtime.log_level:
        return
    write_console(level, _console(level, text))
    file, line_no, function = _site(depth)
    publish_rosout(level, text, file, line_no, function)


def publish_rosout(level: int, text: str, file: str, line: int, function: str) -> None:
    runtime = _state.current()
    if runtime is None or _state.is_shutdown():
        return
    rosout(runtime, level, text, file, line, function)


def rosout(runtime: _state.Runtime, level: int, text: str, file: str, line: int, fn: str) -> None:
    """Publish one ``rosgraph_msgs/Log`` on ``/rosout`` (latched, as rospy's)."""
    node = runtime.node
    pub = getattr(runtime, "rosout", None)
    if pub is None:
        return
    topics = {p.topic.name for p in node.publishers} | {s.name for s in node.subscriptions}
    msg = log_message(
        level,
        text,
        node=node.full_name,
        stamp_ns=runtime.now_ns(),
        file=file,
        line=line,
        function=fn,
        topics=sorted(topics),
    )
    pub.publish(msg)


def log_throttle(period: float, level: int, msg: Any, args: tuple[Any, ...]) -> None:
    file, line, _ = _site(2)
    key = (file, line)
    now = _now_ns()
    last = _last.get(key)
    if last is None or now - last[0] >= period * 1e9 or now < last[0]:
        _last[key] = (now, "")
        log(level, msg, args, depth=3)


def log_throttle_identical(period: float, level: int, msg: Any, args: tuple[Any, ...]) -> None:
    file, line, _ = _site(2)
    key = (file, line)
    text = _text(msg, args)
    now = _now_ns()
    last = _last.get(key)
    if last is None or last[1] != text or now - last[0] >= period * 1e9 or now < last[0]:
        _last[key] = (now, text)
        log(level, text, (), depth=3)


def log_once(level: int, msg: Any, args: tuple[Any, ...]) -> None:
    file, line, _ = _site(2)
    if (file, line) in _once:
        return
    _once.add((file, line))
    log(level, msg, args, depth=3)


def _now_ns() -> int:
    runtime = _state.current()
    return runtime.now_ns() if runtime is not None else time.time_ns()
