"""A node's log, as a ROS 1 node's: each message on ``/rosout`` (``rosgraph_msgs/Log``) and on
the terminal in ROS's format, ``[INFO] [secs.usecs]: text`` (INFO and DEBUG on stdout, WARN
and worse on stderr, as rospy prints them).

The terminal line goes through Python's logging when the application listens to it (the
``belvedere`` command does; so does a script that calls ``logging.basicConfig``): the record
carries the ROS line as ``ros_line`` for a formatter that wants it. A script that configured
nothing gets the line written directly, as rospy writes it: the library adds no handler.
"""

from __future__ import annotations

import logging
import os
import sys
import threading
import time
import traceback
from collections.abc import Callable
from typing import Any, Final, Protocol

from belvedere.graph._endpoints import Publisher, Subscription
from belvedere.graph._executor import Executor
from belvedere.msgs import message_from_data

__all__ = [
    "DEBUG",
    "ERROR",
    "FATAL",
    "INFO",
    "LEVEL_NAMES",
    "WARN",
    "LoggedNode",
    "NodeLogger",
    "console_line",
    "log_message",
    "ros_level",
    "write_console",
]

DEBUG: Final = 1
INFO: Final = 2
WARN: Final = 4
ERROR: Final = 8
FATAL: Final = 16
"""rosgraph_msgs/Log's levels (rospy's ``rospy.INFO`` …)."""
LEVEL_NAMES: Final = {DEBUG: "DEBUG", INFO: "INFO", WARN: "WARN", ERROR: "ERROR", FATAL: "FATAL"}
_COLORS: Final = {DEBUG: "\033[32m", WARN: "\033[33m", ERROR: "\033[31m", FATAL: "\033[31m"}
_BY_LOGGING: Final = (
    (logging.CRITICAL, FATAL),
    (logging.ERROR, ERROR),
    (logging.WARNING, WARN),
    (logging.INFO, INFO),
)
_write_lock = threading.Lock()


class _LoggedGraph(Protocol):
    """What a node's logger uses of the node's graph."""

    @property
    def executor(self) -> Executor: ...
    @property
    def sim_time(self) -> bool: ...
    def now_ns(self) -> int: ...
    def on_executor_thread(self) -> bool: ...


class LoggedNode(Protocol):
    """What a :class:`NodeLogger` uses of its node (a :class:`belvedere.graph.Node`, which
    makes its logger: the logger is handed the node, it does not import the graph)."""

    @property
    def name(self) -> str: ...
    @property
    def full_name(self) -> str: ...
    @property
    def closed(self) -> bool: ...
    @property
    def graph(self) -> _LoggedGraph: ...
    @property
    def publishers(self) -> list[Publisher]: ...
    @property
    def subscriptions(self) -> list[Subscription]: ...
    def publisher(
        self, topic: str, msg_type: str, *, queue_size: int = ..., latch: bool = ...
    ) -> Publisher: ...


def ros_level(levelno: int) -> int:
    """The ROS level of a Python logging level (CRITICAL is FATAL, WARNING is WARN …)."""
    return next((ros for py, ros in _BY_LOGGING if levelno >= py), DEBUG)


def console_line(level: int, text: str, *, node: str, sim_ns: int | None = None) -> str:
    """The terminal line of a log message, as rospy formats it: ``ROSCONSOLE_FORMAT``
    (default ``[${severity}] [${time}]: ${message}``); the time is the wall clock's, then the
    graph's (``wall, sim``) when it is simulated."""
    wall = f"{time.time():f}"
    line = os.environ.get("ROSCONSOLE_FORMAT", "[${severity}] [${time}]: ${message}")
    line = line.replace("${severity}", LEVEL_NAMES[level]).replace("${message}", text)
    line = line.replace("${walltime}", wall).replace("${node}", node)
    stamp = wall if sim_ns is None else f"{wall}, {sim_ns / 1e9:f}"
    return line.replace("${time}", stamp)


def write_console(level: int, line: str) -> None:
    """Print a log line as rospy does: below WARN on stdout, the rest on stderr, coloured on a
    terminal."""
    stream = sys.stdout if level < WARN else sys.stderr
    color = _COLORS.get(level)
    if color is not None and stream.isatty():
        line = f"{color}{line}\033[0m"
    with _write_lock:
        stream.write(line + "\n")
        stream.flush()


def log_message(
    level: int,
    text: str,
    *,
    node: str,
    stamp_ns: int,
    file: str,
    line: int,
    function: str,
    topics: list[str],
) -> Any:
    """The ``rosgraph_msgs/Log`` a node publishes on ``/rosout`` for one message."""
    sec, nanosec = divmod(stamp_ns, 1_000_000_000)
    data = {
        "header": {"stamp": {"sec": sec, "nanosec": nanosec}},
        "level": level,
        "name": node,
        "msg": text,
        "file": file,
        "function": function,
        "line": line,
        "topics": topics,
    }
    return message_from_data("rosgraph_msgs/Log", data)


class NodeLogger:
    """A node's logger (``node.logger``): ``info``, ``warning`` … as Python's loggers take
    them (``%`` arguments, ``exc_info``), each message also on ``/rosout`` and on the terminal
    in ROS's format (see the module). Messages below the node's level are dropped: INFO unless
    :meth:`setLevel` says otherwise, or what the application set Python's logging to."""

    def __init__(self, node: LoggedNode) -> None:
        self.node = node
        self.logger = logging.getLogger(f"belvedere.node.{node.name}")
        """The Python logger the records go through (when anything listens to it)."""
        self._level: int | None = None
        self._rosout: Publisher | None = None

    @property
    def name(self) -> str:
        return self.logger.name

    def setLevel(self, level: int) -> None:  # noqa: N802 (Python logging's name)
        """The node's level (a Python logging level: ``logging.DEBUG`` shows debug)."""
        self._level = level
        self.logger.setLevel(level)

    def getEffectiveLevel(self) -> int:  # noqa: N802 (Python logging's name)
        if self._level is not None:
            return self._level
        if self.logger.hasHandlers():
            return self.logger.getEffectiveLevel()
        return logging.INFO

    def isEnabledFor(self, level: int) -> bool:  # noqa: N802 (Python logging's name)
        return level >= self.getEffectiveLevel()

    def debug(self, msg: object, *args: object, **kwargs: Any) -> None:
        self._log(logging.DEBUG, msg, args, **kwargs)

    def info(self, msg: object, *args: object, **kwargs: Any) -> None:
        self._log(logging.INFO, msg, args, **kwargs)

    def warning(self, msg: object, *args: object, **kwargs: Any) -> None:
        self._log(logging.WARNING, msg, args, **kwargs)

    warn = warning

    def error(self, msg: object, *args: object, **kwargs: Any) -> None:
        self._log(logging.ERROR, msg, args, **kwargs)

    def exception(self, msg: object, *args: object, **kwargs: Any) -> None:
        kwargs.setdefault("exc_info", True)
        self._log(logging.ERROR, msg, args, **kwargs)

    def critical(self, msg: object, *args: object, **kwargs: Any) -> None:
        self._log(logging.CRITICAL, msg, args, **kwargs)

    fatal = critical

    def log(self, level: int, msg: object, *args: object, **kwargs: Any) -> None:
        self._log(level, msg, args, **kwargs)

    def _log(
        self,
        levelno: int,
        msg: object,
        args: tuple[object, ...],
        *,
        exc_info: Any = None,
        stacklevel: int = 1,
    ) -> None:
        if not self.isEnabledFor(levelno):
            return
        text = str(msg) % args if args else str(msg)
        if exc_info:
            text += "\n" + _traceback(exc_info)
        level = ros_level(levelno)
        node = self.node
        graph = node.graph
        frame = sys._getframe(1 + stacklevel)
        site = (frame.f_code.co_filename, frame.f_lineno, frame.f_code.co_name)
        stamp_ns = graph.now_ns()
        self._publish(level, text, stamp_ns, site)
        line = console_line(
            level, text, node=node.full_name, sim_ns=stamp_ns if graph.sim_time else None
        )
        if self.logger.hasHandlers():
            self.logger.log(
                levelno,
                msg,
                *args,
                exc_info=exc_info,
                stacklevel=2 + stacklevel,
                extra={"ros_line": line},
            )
        else:
            write_console(level, line)

    def _publish(self, level: int, text: str, stamp_ns: int, site: tuple[str, int, str]) -> None:
        """The message on ``/rosout``, from the executor's thread (the publisher is made
        there the first time: a node that never logs has none)."""
        node = self.node

        def publish() -> None:
            if node.closed:
                return
            if self._rosout is None:
                self._rosout = node.publisher(
                    "/rosout", "rosgraph_msgs/Log", latch=True, queue_size=100
                )
            topics = {p.name for p in node.publishers} | {s.name for s in node.subscriptions}
            self._rosout.publish(
                log_message(
                    level,
                    text,
                    node=node.full_name,
                    stamp_ns=stamp_ns,
                    file=site[0],
                    line=site[1],
                    function=site[2],
                    topics=sorted(topics),
                )
            )

        _on_executor(node, publish)


def _traceback(exc_info: Any) -> str:
    """The traceback ``exc_info`` names (True: the exception being handled), as logging
    prints it."""
    if isinstance(exc_info, BaseException):
        lines = traceback.format_exception(exc_info)
    elif isinstance(exc_info, tuple):
        lines = traceback.format_exception(*exc_info)
    else:
        lines = traceback.format_exception(*sys.exc_info())
    return "".join(lines).rstrip("\n")


def _on_executor(node: LoggedNode, fn: Callable[[], None]) -> None:
    graph = node.graph
    if graph.on_executor_thread():
        fn()
    else:
        graph.executor.post(fn)
