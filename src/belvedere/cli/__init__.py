"""``belvedere <verb>``: the command line.

Every verb is a module here with ``add_parser(subparsers)`` and ``run(args) -> int``. Any
:class:`~belvedere.errors.BelvedereError` prints as one ``error: …`` message and exits 1
(usage errors exit 2); a traceback appears only with ``--debug``.
"""

from __future__ import annotations

import argparse
import atexit
import contextlib
import faulthandler
import gc
import importlib
import logging
import os
import re
import signal
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from typing import Final, NoReturn, TextIO

from belvedere import __version__
from belvedere.errors import BelvedereError

__all__ = ["console", "hand_over", "main"]

_VERBS = (
    "xacro",
    "check",
    "display",
    "sim",
    "launch",
    "teleop",
    "topic",
    "param",
    "service",
    "node",
    "msg",
    "srv",
    "wtf",
    "log",
    "tf",
    "bag",
    "foxglove",
    "roscore",
    "run",
    "rospack",
    "map",
    "slam",
    "world",
    "batch",
    "test",
)
"""The verbs, in the order ``--help`` lists them; each is the module ``belvedere.cli.VERB``.
Only the verb being run is imported (``xacro`` need not load the simulator)."""


_OWN_PREFIX = re.compile(r"(?:^|: )(?:warning|error|note): ")


class _Formatter(logging.Formatter):
    """Plain messages for info; ``warning:`` prefixes unless the message carries its own
    (``file:line: error: …``)."""

    def format(self, record: logging.LogRecord) -> str:
        ros_line: str | None = getattr(record, "ros_line", None)
        if ros_line is not None:
            return ros_line  # a node's log, in ROS's format (see belvedere.graph.NodeLogger)
        msg = record.getMessage()
        if getattr(record, "verbatim", False):
            return msg  # roslaunch's own lines (belvedere.launch._lifecycle)
        own_prefix = _OWN_PREFIX.search(msg) is not None
        if record.levelno >= logging.WARNING and not own_prefix:
            msg = f"{record.levelname.lower()}: {msg}"
        return msg


class _StderrHandler(logging.StreamHandler):  # type: ignore[type-arg]
    """Writes to whatever ``sys.stderr`` is when a record comes, never to a stream that was
    replaced (and perhaps closed) since, as a test's capture is. A node's INFO and DEBUG go
    to stdout, as a ROS node prints them, unless ``--echo`` has stdout to itself."""

    _to_stdout = False

    def __init__(self, *, node_logs_on_stdout: bool = True) -> None:
        super().__init__()
        self.node_logs_on_stdout = node_logs_on_stdout

    def emit(self, record: logging.LogRecord) -> None:
        # (called with the handler's lock held)
        node_log = getattr(record, "ros_line", None) is not None
        self._to_stdout = self.node_logs_on_stdout and node_log and record.levelno < logging.WARNING
        super().emit(record)

    @property
    def stream(self) -> TextIO:
        return sys.stdout if self._to_stdout else sys.stderr

    @stream.setter
    def stream(self, _: TextIO) -> None:
        pass  # StreamHandler sets it; the property decides


_LEVELS = {-2: logging.ERROR, -1: logging.WARNING, 0: logging.INFO, 1: logging.DEBUG}
"""The ``belvedere`` logger's level by ``-v`` count minus ``-q`` count (clamped)."""


@contextlib.contextmanager
def _logging_to_stderr(verbosity: int, *, node_logs_on_stdout: bool = True) -> Iterator[None]:
    """The library's records on stderr while a command runs; as before once it returns
    (``main()`` is called in-process too, by tests and scripts). ``-q`` hides notices
    (info), ``-qq`` warnings too, ``-v`` shows debug records (see :mod:`._report`). Nodes'
    INFO and DEBUG lines go to stdout, as ROS nodes print them, unless not
    ``node_logs_on_stdout``."""
    level = _LEVELS[max(min(_LEVELS), min(verbosity, max(_LEVELS)))]
    handler = _StderrHandler(node_logs_on_stdout=node_logs_on_stdout)
    handler.setFormatter(_Formatter())
    root = logging.getLogger("belvedere")
    handlers, old_level, propagate = root.handlers[:], root.level, root.propagate
    root.handlers[:] = [handler]
    root.setLevel(level)
    root.propagate = False
    try:
        yield
    finally:
        root.handlers[:] = handlers
        root.setLevel(old_level)
        root.propagate = propagate


def _common_options(*, suppress: bool) -> argparse.ArgumentParser:
    """Options valid before and after the verb. After it, defaults are suppressed so they do
    not overwrite what was given before it."""

    def default(value: object) -> object:
        return argparse.SUPPRESS if suppress else value

    common = argparse.ArgumentParser(add_help=False)
    common.add_argument(
        "-v",
        "--verbose",
        action="count",
        default=default(0),
        help="more output: every deprecation with its file:line, debug records",
    )
    common.add_argument(
        "-q",
        "--quiet",
        action="count",
        default=default(0),
        help="less output: no notices or summaries (-qq: no warnings either; errors stay)",
    )
    common.add_argument(
        "--debug", action="store_true", default=default(False), help="show tracebacks on errors"
    )
    common.add_argument(
        "--package-path",
        action="append",
        default=default([]),
        metavar="DIR",
        help="search DIR for ROS packages (before BELVEDERE_PACKAGE_PATH, ROS_PACKAGE_PATH)",
    )
    return common


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The command line; with ``only``, just that verb's options are built (and imported)."""
    common = _common_options(suppress=True)
    parser = argparse.ArgumentParser(
        prog="belvedere",
        description="The ROS robot-modelling and simulation workflow, with no ROS to install.",
        parents=[_common_options(suppress=False)],
    )
    parser.add_argument("--version", action="version", version=f"belvedere {__version__}")
    sub = parser.add_subparsers(dest="verb", metavar="VERB", required=True)
    for verb in _VERBS:
        if only is None or verb == only:
            importlib.import_module(f"belvedere.cli.{verb}").add_parser(sub, common)
    return parser


def _verb_of(argv: list[str]) -> str | None:
    """The verb the command line names, if it names one we have."""
    _, rest = _common_options(suppress=False).parse_known_args(argv)
    first = next((a for a in rest if not a.startswith("-")), None)
    return first if first in _VERBS else None


_handover: list[Callable[[], NoReturn]] = []
"""What takes the ``belvedere`` command's process over once :func:`main` has returned."""
_in_command = False
"""Whether :func:`main` runs as the ``belvedere`` command (:func:`console`)."""


def hand_over(action: Callable[[], NoReturn]) -> bool:
    """Have ``action`` take this process over once the verb has returned and the command
    line's set-up is undone (its logging, its Ctrl-C handler): ``belvedere run SCRIPT``
    runs the script in the command's own process, as ``python3 script.py`` would, rather
    than starting a second Python. True if it will; False when :func:`main` is called some
    other way (a test, a program), whose process is not the verb's to give."""
    if not _in_command or _handover:
        return False
    _handover.append(action)
    return True


def console() -> NoReturn:
    """The ``belvedere`` command: :func:`main`, then exit as Python exits (threads joined,
    exit handlers run) but without the interpreter's finalization.

    Finalization collects the run's garbage (a large expansion leaves a few hundred
    thousand nodes in reference cycles: a tenth of a second the operating system saves by
    freeing the process at once), and a Zenoh thread still delivering a sample (another
    graph's ``/clock``) when it starts aborts the process ("FATAL: exception not
    rethrown")."""
    global _in_command
    for signum in _ENDING_SIGNALS:
        signal.signal(signum, _interrupted)
    _in_command = True
    code = main()
    if _handover:
        signal.signal(signal.SIGINT, signal.default_int_handler)
        for signum in _ENDING_SIGNALS[1:]:
            signal.signal(signum, signal.SIG_DFL)
        _handover[0]()
    gc.freeze()
    # Nothing hangs: a thread that does not end is named (its stack) and the process ends.
    faulthandler.dump_traceback_later(SHUTDOWN_S, exit=True)
    threading._shutdown()  # type: ignore[attr-defined]
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError):  # a closed pipe, a closed stream
            stream.flush()
    os._exit(code)


SHUTDOWN_S = 20.0
"""How long ending may take once asked to (Ctrl-C, or the verb is done) before the process
prints every thread's stack and exits."""


_ENDING_SIGNALS: Final = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
"""Ctrl-C, ``kill`` and a closed terminal: each ends a verb cleanly, as roslaunch ends on
them, so a launch stopped by ``kill`` stops its nodes' processes too instead of leaving them
running without it."""


def _interrupted(signum: int, frame: object) -> None:
    """Ctrl-C (or SIGTERM, SIGHUP): end as Python would on Ctrl-C (KeyboardInterrupt), but
    never wait forever for it."""
    faulthandler.dump_traceback_later(SHUTDOWN_S, exit=True)
    raise KeyboardInterrupt


def main(argv: Sequence[str] | None = None) -> int:
    args_list = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser(_verb_of(args_list))
    try:
        args, extra = parser.parse_known_args(args_list)
    except SystemExit as exc:  # argparse: --help/--version exit 0, usage errors exit 2
        return int(exc.code or 0)
    args.extra = extra
    # --echo has stdout to itself (a stream of YAML documents): nodes' lines go to stderr
    echo = bool(getattr(args, "echo", None))
    with _logging_to_stderr(args.verbose - args.quiet, node_logs_on_stdout=not echo):
        try:
            code: int = args.run(args)
            return code
        except BelvedereError as err:
            if args.debug:
                import traceback

                traceback.print_exc()
            sys.stderr.write(err.describe() + "\n")
            return 1
        except KeyboardInterrupt:
            return 130
        except BrokenPipeError:
            return 1
