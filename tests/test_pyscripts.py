"""The user's scripts as belvedere runs them: Python 2 translated once (cached) and run as
the original file, Windows line ends, and one error at the line for what compiles neither
way."""

from __future__ import annotations

import logging
import os
import subprocess
from pathlib import Path

import pytest

from belvedere import bounded, pyscripts
from belvedere.pyscripts import ScriptError, script_command

PY2 = """#!/usr/bin/env python
import sys, os
name = os.path.basename(__file__)
print "hello from", name, sys.argv[1:]
d = {"a": 1}
if d.has_key("a"):
    print >>sys.stderr, "python 2 idioms work"
try:
    raise ValueError, "old raise"
except ValueError, e:
    print "caught", e
"""


@pytest.fixture(autouse=True)
def _cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))


def _run(command: list[str], *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*command, *args], capture_output=True, text=True, timeout=60, check=False
    )


def test_python_3_runs_as_it_is(tmp_path: Path) -> None:
    script = tmp_path / "ok.py"
    script.write_text("import sys\nprint('fine', __file__, sys.argv)\n")
    command = script_command(script)
    assert str(script) in command
    assert not (tmp_path / "cache").exists()  # nothing to translate, nothing cached
    done = _run(command, "a:=b")
    assert done.stdout == f"fine {script} {[str(script), 'a:=b']}\n"


def test_python_2_is_translated_once_and_runs_as_the_original(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    script = tmp_path / "teleop.py"
    script.write_text(PY2)
    with caplog.at_level(logging.WARNING, logger="belvedere.scripts"):
        command = script_command(script)
    assert [r.getMessage().split(": running")[0] for r in caplog.records] == [
        f"{script}: a Python 2 script"
    ]
    cached = list((tmp_path / "cache" / "belvedere" / "scripts").iterdir())
    assert len(cached) == 1
    done = _run(command, "x", "_speed:=1")
    assert done.returncode == 0, done.stderr
    # __file__ and argv are the original's
    assert done.stdout == "hello from teleop.py ['x', '_speed:=1']\ncaught old raise\n"
    assert done.stderr == "python 2 idioms work\n"
    script_command(script)  # the same content: the cached translation, no new file
    assert list((tmp_path / "cache" / "belvedere" / "scripts").iterdir()) == cached


def test_windows_line_ends_and_their_shebang(tmp_path: Path) -> None:
    script = tmp_path / "crlf.py"
    script.write_bytes(b"#!/usr/bin/env python\r\nprint 'crlf'\r\n")
    done = _run(script_command(script))
    assert (done.returncode, done.stdout) == (0, "crlf\n")


def test_what_compiles_neither_way_is_one_error_at_its_line(tmp_path: Path) -> None:
    script = tmp_path / "broken.py"
    script.write_text("x = 1\n\ndef f(:\n    pass\n")
    with pytest.raises(ScriptError, match=r"broken\.py:3:\d+: error: not valid Python"):
        script_command(script)


def test_a_translated_scripts_traceback_names_the_original_line(tmp_path: Path) -> None:
    script = tmp_path / "fails.py"
    script.write_text('print "start"\n\n\nraise RuntimeError, "at line 4"\n')
    done = _run(script_command(script))
    assert done.returncode == 1
    assert f'File "{script}", line 4' in done.stderr


# --- scripts from the internet ------------------------------------------------------------------


@pytest.mark.parametrize(
    ("body", "why"),
    [
        ('print "2"\nx = ' + "(" * 1000 + "1" + ")" * 1000, "nested too deeply to translate"),
        ('print "2"\nx = ' + "[" * 1000 + "]" * 1000, "nested too deeply to translate"),
        ('print "2"\nx = ' + "-" * 100_000 + "1", "nested too deeply to translate"),
        ("x = " + "-" * 100_000 + "1", "it nests deeper than Python can compile"),
    ],
    ids=["parentheses", "lists", "unary-minus-2", "unary-minus-3"],
)
def test_a_script_nested_past_what_python_or_the_translator_follow_is_one_error(
    tmp_path: Path, body: str, why: str
) -> None:
    script = tmp_path / "deep.py"
    script.write_text(body + "\n")
    with pytest.raises(ScriptError, match=rf"/deep\.py: error: .*{why}") as caught:
        script_command(script)
    assert caught.value.location is not None
    assert caught.value.location.path == str(script)


def test_a_translation_that_takes_too_long_is_stopped(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(bounded, "SCRIPT_SECONDS", 0.01)  # less than Python needs to start
    script = tmp_path / "slow.py"
    script.write_text(PY2)
    with pytest.raises(
        ScriptError, match=r"slow\.py: error: .*translating it from Python 2 took more than 0\.01 s"
    ):
        script_command(script)
    assert not (tmp_path / "cache").exists()


def test_a_script_past_the_cap_runs_as_it_is_unchecked(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    monkeypatch.setattr(pyscripts, "SCRIPT_BYTES", 16)
    script = tmp_path / "big.py"
    script.write_text("print('a script of more than 16 bytes')\n")
    with caplog.at_level(logging.WARNING, logger="belvedere.scripts"):
        command = script_command(script)
    assert [r.getMessage() for r in caplog.records] == [
        f"{script}: more than 16 bytes: run as it is, unchecked (belvedere checks and "
        "translates from Python 2 only scripts of up to that size)"
    ]
    assert _run(command).stdout == "a script of more than 16 bytes\n"


@pytest.mark.parametrize("kind", ["fifo", "dir"])
def test_a_script_that_is_not_a_regular_file_is_refused_unread(tmp_path: Path, kind: str) -> None:
    script = tmp_path / "node.py"
    if kind == "fifo":
        os.mkfifo(script)
    else:
        script.mkdir()
    with pytest.raises(ScriptError, match=r"node\.py: error: cannot read the script: it is a"):
        script_command(script)
