"""The user's scripts in their own processes, as Python 3.9+, rosrun and roslaunch run them:
``__file__`` is an absolute path (a script finds its files after a ``cd``), a traceback names
the script's file and starts at its own frame, and ``belvedere run SCRIPT`` runs the script
in the command's own process (one Python starting, as with ``python3 script.py``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from tests.waiting import DEADLINE

BELVEDERE = [sys.executable, "-m", "belvedere"]

FACTS = """\
import json, logging, os, signal, sys
import __main__
here = os.path.dirname(__file__)
os.chdir("/")  # a script that moves on still finds its files by its own path
with open(os.path.join(here, "data.txt")) as f:
    data = f.read()
print(json.dumps({
    "file": __file__, "argv": sys.argv, "path0": sys.path[0], "name": __name__,
    "main_is_this": getattr(__main__, "here", None) == here, "data": data,
    "sigint_default": signal.getsignal(signal.SIGINT) is signal.default_int_handler,
    "logging": [len(logging.getLogger(n).handlers) for n in ("", "belvedere")],
    "pid": os.getpid(),
}))
"""
"""A script that says what it sees of itself (as JSON)."""


def _facts_script(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "data.txt").write_text("found")
    script = folder / "probe.py"
    script.write_text(FACTS)
    return script


def _run(argv: list[str], cwd: Path, **env: str) -> tuple[int, dict[str, Any], str]:
    """Run ``argv`` to its end: its exit status, the facts it printed, its stderr."""
    proc = subprocess.Popen(
        argv,
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, **env},
    )
    out, err = proc.communicate(timeout=DEADLINE)
    lines = [line for line in out.splitlines() if line.startswith("{")]
    facts = json.loads(lines[-1]) if lines else {}
    facts["process"] = proc.pid
    return proc.returncode, facts, err


@pytest.mark.parametrize("typed", ["./probe.py", "t1/probe.py"])
def test_a_script_sees_itself_as_python3_shows_it(tmp_path: Path, peer: Any, typed: str) -> None:
    """Beside a running graph (the ``peer``), ``belvedere run SCRIPT`` and ``python3 SCRIPT``
    show the script the same ``__file__`` (absolute), ``argv``, ``sys.path[0]``, ``__main__``,
    Ctrl-C handling and logging set-up; and it is the command's own process."""
    _facts_script(tmp_path / Path(typed).parent)
    status, ours, err = _run([*BELVEDERE, "run", typed, "a", "_k:=1"], tmp_path)
    assert status == 0, err
    python_status, python, err = _run([sys.executable, typed, "a", "_k:=1"], tmp_path)
    assert python_status == 0, err
    assert ours["file"] == str(tmp_path / typed.removeprefix("./"))
    for key in ("argv", "path0", "name", "main_is_this", "data", "sigint_default", "logging"):
        assert ours[key] == python[key], key
    assert ours["pid"] == ours["process"]  # one process: no second Python to start


def test_a_script_run_alone_knows_its_absolute_path(tmp_path: Path) -> None:
    """With no graph running, ``run`` provides one and runs the script beside it: its
    ``__file__`` is absolute too."""
    _facts_script(tmp_path / "t1")
    status, facts, err = _run([*BELVEDERE, "run", "--headless", "t1/probe.py"], tmp_path)
    assert status == 0, err
    assert facts["file"] == str(tmp_path / "t1" / "probe.py")
    assert facts["data"] == "found"


def _package(root: Path, name: str) -> Path:
    pkg = root / name
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "package.xml").write_text(f"<package><name>{name}</name></package>")
    return pkg


def test_rosrun_gives_a_packages_script_its_absolute_path(tmp_path: Path, peer: Any) -> None:
    pkg = _package(tmp_path / "src", "learner")
    script = _facts_script(pkg / "scripts")
    # the package path as a relative one: rosrun still passes the script's absolute path
    argv = [*BELVEDERE, "run", "--package-path", "src", "learner", "probe.py", "x"]
    status, facts, err = _run(argv, tmp_path)
    assert status == 0, err
    assert facts["file"] == str(script)
    assert facts["argv"] == [str(script), "x"]
    assert facts["pid"] == facts["process"]


BOOM = """\
import os
os.chdir("/")


def fail():
    raise RuntimeError("boom")


fail()
"""


def _frames(stderr: str) -> list[str]:
    return [line.strip() for line in stderr.splitlines() if line.strip().startswith("File ")]


def test_a_launched_scripts_traceback_is_its_own(tmp_path: Path, endpoint: str) -> None:
    """A script node's traceback names its file (absolute) from its own frame on: nothing of
    belvedere's start-up code (``File "<string>"``)."""
    pkg = _package(tmp_path, "mypkg")
    script = pkg / "scripts" / "boom.py"
    script.write_text(BOOM)
    launch = pkg / "boom.launch"
    launch.write_text(
        '<launch><node pkg="mypkg" type="boom.py" name="boom" required="true" '
        'output="screen"/></launch>'
    )
    done = subprocess.run(
        [*BELVEDERE, "launch", str(launch), "--headless", "--duration", str(DEADLINE)],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )
    assert _frames(done.stderr) == [
        f'File "{script}", line 9, in <module>',
        f'File "{script}", line 6, in fail',
    ], done.stderr
    assert "RuntimeError: boom" in done.stderr


def test_a_python_2_scripts_file_and_traceback_are_the_originals(tmp_path: Path, peer: Any) -> None:
    """A Python 2 script runs from its translation (cached elsewhere), but it is the original
    that ``__file__`` and its traceback name."""
    script = tmp_path / "t1" / "old.py"
    script.parent.mkdir()
    script.write_text('print "file", __file__\n\n\nraise ValueError, "old style"\n')
    done = subprocess.run(
        [*BELVEDERE, "run", "t1/old.py"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
        env={**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")},
    )
    assert done.returncode == 1
    assert done.stdout == f"file {script}\n"
    assert _frames(done.stderr) == [f'File "{script}", line 4, in <module>'], done.stderr
    assert "ValueError: old style" in done.stderr
