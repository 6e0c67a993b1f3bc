"""The user's Python scripts as belvedere runs them (``launch``'s script nodes, ``run``).

The course's scripts are often Python 2 (``print "..."``) and sometimes have Windows line ends,
which break their shebang. A script that does not compile as Python 3 is translated with
fissix (a maintained lib2to3) once per content — the translation is cached — with one notice
naming it; it then runs as itself (its ``__file__``, ``sys.argv[0]`` and directory on the path
are the original's). A script that compiles neither way is one error at its line.
"""

from __future__ import annotations

import hashlib
import logging
import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Final, NoReturn

from belvedere import bounded
from belvedere.bounded import (
    DATA_FILE_BYTES,
    SCRIPT_BYTES,
    LimitError,
    describe_size,
    open_regular,
)
from belvedere.errors import ParseError, SourceLocation
from belvedere.fileio import write_file

__all__ = ["SITE", "Script", "ScriptError", "cache_dir", "prepare_script", "script_command"]

logger = logging.getLogger("belvedere.scripts")

_BOOT: Final = """\
import sys
here = sys.path.pop(0)  # the working directory: never where belvedere itself comes from
from belvedere._scriptmain import run_as_main
sys.path.insert(0, here)
run_as_main(*sys.argv[1:5], sys.argv[5:])
"""
"""A script's process starts here: :func:`belvedere._scriptmain.run_as_main` with the
script's ``argv[0]``, its file, what runs (the file or its translation) and :data:`SITE`."""

SITE: Final = Path(__file__).parent / "ros1" / "site"
"""belvedere's ``rospy``, ``tf``, ``tf2_ros``, ``actionlib``, ``roslib``, ``rospkg``: only the
scripts belvedere runs have it on their path, so they never shadow a real ROS elsewhere."""


class ScriptError(ParseError):
    """A script that compiles neither as Python 3 nor as translated Python 2."""


def cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "belvedere" / "scripts"


def _decode(data: bytes) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1")  # Python 2's default source encoding was ASCII-ish


def _compiles(text: str, path: Path) -> SyntaxError | None:
    """The error that keeps ``text`` from compiling as Python 3, if any.

    Raises:
        ScriptError: it nests deeper than Python's compiler goes (Python itself could not run
            it either).
    """
    try:
        compile(text, str(path), "exec", dont_inherit=True)
    except SyntaxError as err:
        return err
    except (RecursionError, MemoryError):  # CPython's parser and compiler: "too nested"
        msg = "it nests deeper than Python can compile (a generated or hostile file?)"
        raise ScriptError(msg, SourceLocation(str(path))) from None
    return None


_TRANSLATE: Final = """\
import resource, sys
memory = int(sys.argv[2])
resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
from fissix import refactor
from fissix.pgen2.parse import ParseError
source = sys.stdin.buffer.read().decode("utf-8")
tool = refactor.RefactoringTool(refactor.get_fixers_from_package("fissix.fixes"))
try:
    out = str(tool.refactor_string(source, sys.argv[1]))
except ParseError as err:
    line, col = err.context[1] if err.context else (0, 0)
    print(line, col)
    sys.exit(3)
except RecursionError:
    sys.exit(4)
except MemoryError:
    sys.exit(5)
sys.stdout.buffer.write(out.encode("utf-8"))
"""
"""Translates the Python 2 on its stdin with fissix (a maintained lib2to3) and prints it;
exit status 3 (and the line and column) for what its grammar refuses, 4 for nesting deeper
than it recurses, 5 for running out of the memory it is given."""

_TRANSLATE_MEMORY: Final = 2 << 30
"""Address space the translating process may take (it needs ~250 MiB for 512 KiB)."""


def _translate(text: str, path: Path) -> str:
    """``text`` translated from Python 2, in a process of its own: fissix takes time that
    grows faster than the script in some shapes (20,000 adjacent string literals take 11 s,
    40,000 four times that), so it runs bounded by :data:`~belvedere.bounded.SCRIPT_SECONDS`
    and its memory, and can be stopped. It is done once per script content (cached)."""
    source = text if text.endswith("\n") else text + "\n"
    at = SourceLocation(str(path))
    seconds = bounded.SCRIPT_SECONDS
    argv = [sys.executable, "-c", _TRANSLATE, str(path), str(_TRANSLATE_MEMORY)]
    try:
        ran = bounded.run_bounded(
            argv, seconds=seconds, limit=8 * bounded.SCRIPT_BYTES, stdin=source.encode("utf-8")
        )
    except OSError as err:
        msg = f"not valid Python 3, and the Python 2 translator cannot start: {err}"
        raise ScriptError(msg, at) from None
    if ran.status == 0:
        return ran.stdout.decode("utf-8")
    lead = "not valid Python 3, and"
    if ran.stopped == "time":
        msg = f"{lead} translating it from Python 2 took more than {seconds:g} s: stopped"
    elif ran.status == 3:
        line, col = (int(n) for n in ran.stdout.split()[:2])
        msg = f"{lead} not Python 2 that can be translated"
        at = SourceLocation(str(path), line, col + 1)
    elif ran.status == 4:
        msg = f"{lead} nested too deeply to translate from Python 2"
    elif ran.status == 5 or ran.stopped:
        msg = f"{lead} too large to translate from Python 2 (the translator ran out of room)"
    else:
        status = ran.status or 0
        tail = ran.stderr.decode("utf-8", errors="replace").strip().splitlines()[-1:]
        msg = f"{lead} the Python 2 translator failed (status {status}): {''.join(tail)}"
    raise ScriptError(msg, at)


@dataclass(frozen=True)
class Script:
    """A user's script, ready to run (see :func:`prepare_script`)."""

    argv0: str
    """Its ``sys.argv[0]``: the path as the user typed it (``belvedere run ./probe.py``), or
    the absolute path rosrun and roslaunch pass."""
    file: str
    """Its ``__file__`` and the name tracebacks give: its absolute path, as Python 3.9+ and
    rosrun give it, so ``os.path.dirname(__file__)`` finds the script's files after a ``cd``."""
    runnable: str
    """What runs: :attr:`file`, or its Python 3 form (cached)."""

    def command(self, python: str = sys.executable) -> list[str]:
        """The command that runs the script in a process of its own (before its arguments)."""
        return [python, "-c", _BOOT, self.argv0, self.file, self.runnable, str(SITE)]

    def run_here(self, args: Sequence[str]) -> NoReturn:
        """Run the script as this process's main program, with ``args``; the process ends
        with it (its exit status). Only for a process that has nothing else to do."""
        from belvedere._scriptmain import run_as_main

        run_as_main(self.argv0, self.file, self.runnable, str(SITE), args)


def script_command(path: Path, python: str = sys.executable) -> list[str]:
    """The command that runs ``path`` (before its own arguments), as roslaunch runs a node's
    script: see :func:`prepare_script`."""
    return prepare_script(path).command(python)


def prepare_script(path: Path | str, *, argv0: str | None = None) -> Script:
    """``path`` checked and, if need be, translated (``argv0``: its ``sys.argv[0]``, by
    default its absolute path).

    Only a regular file is read. A script of at most :data:`~belvedere.bounded.SCRIPT_BYTES`
    is checked (compiled) and, if need be, translated; a larger one runs as it is, unchecked
    (compiling or translating it here would take the time and memory of a much larger
    program), with a warning that says so.

    Raises:
        ScriptError: the script cannot be read, or compiles neither as Python 3 nor as
            translated Python 2 (at its line), or nests too deeply to compile or translate.
    """
    file = os.path.abspath(path)
    ready = partial(Script, file if argv0 is None else argv0, file)
    path = Path(path)
    try:
        # any size: only what is checked is read (a larger script is Python's to read)
        with open_regular(path, limit=DATA_FILE_BYTES, what="", name="the script") as f:
            data = f.read(SCRIPT_BYTES + 1)
    except LimitError as err:
        raise ScriptError(err.message, SourceLocation(str(path))) from None
    if len(data) > SCRIPT_BYTES:
        logger.warning(
            "%s: more than %s: run as it is, unchecked (belvedere checks and translates "
            "from Python 2 only scripts of up to that size)",
            path,
            describe_size(SCRIPT_BYTES),
        )
        return ready(file)
    text = _decode(data)
    crlf = "\r\n" in text
    if crlf:
        text = text.replace("\r\n", "\n")
    problem = _compiles(text, path)
    if problem is None and not crlf:
        return ready(file)
    what = "Windows line ends"
    if problem is not None:
        translated = _translate(text, path)
        still = _compiles(translated, path)
        if still is not None:
            where = SourceLocation(str(path), problem.lineno or 0, problem.offset or 0)
            msg = f"not valid Python (3, or 2 translated): {problem.msg}"
            raise ScriptError(msg, where)
        text, what = translated, "Python 2"
    digest = hashlib.sha256(data).hexdigest()[:20]
    runnable = cache_dir() / f"{digest}.py"
    if not runnable.is_file():
        runnable.parent.mkdir(parents=True, exist_ok=True)
        write_file(runnable, text)
    logger.warning(
        "%s: %s: running its Python 3 form (cached as %s)",
        path,
        "a Python 2 script" if what == "Python 2" else "Windows line ends",
        runnable,
    )
    return ready(str(runnable))
