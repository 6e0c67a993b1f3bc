"""``belvedere param`` against Debian's ``rosparam``: one sequence of commands run by rosparam
on a fresh roscore and by ``belvedere param`` on a graph of its own, every command's stdout
(and a dumped file) compared line for line, unnormalised, and its exit status.

Left out is what Debian's rosparam cannot do under Python 3 (it fails with a traceback):
``get``/``dump`` of a binary value, a null value, a document that is a scalar. Both tools
print errors on stderr, which is not compared (rosparam writes ``ERROR: Parameter [/x] is not
set``, belvedere ``error: parameter '/x' is not set``).

Skipped where Debian's ROS 1 (roscore, rosparam) is absent."""

from __future__ import annotations

import io
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from belvedere.cli import main
from tests.ros1.rospy_oracle import Master, master, missing_oracle
from tests.waiting import DEADLINE

pytestmark = pytest.mark.oracle

ROSPARAM = Path("/usr/bin/rosparam")

PARAMS_YAML = """\
speed: 0.5
angle: !degrees 90
turn: !radians pi/2
half: deg(180)
full: rad(pi)
nest: {z: 1, a: [1, 2], e: {}}
name: robot
---
_ns: second
k: v
"""

Command = tuple[str, ...]


def _commands(files: Path) -> list[Command]:
    """The sequence; ``files`` holds the files it reads and writes."""
    p = str(files / "params.yaml")
    values: list[Command] = [
        ("set", "/t/i", "1"),
        ("set", "/t/f", "1.5"),
        ("set", "/t/small", "1.0e-5"),
        ("set", "/t/b", "true"),
        ("set", "/t/s", "hello"),
        ("set", "/t/n", "'42'"),  # a string that looks like a number
        ("set", "/t/e", ""),  # the empty string
        ("set", "/t/l", "[1, 2.5, a, true]"),
        ("set", "-v", "/t/d", '{b: 1, a: {c: x, d: [1, 2]}, m: "one\\ntwo"}'),
        ("set", "/t/neg", "-3"),
        ("set", "/t/word", "1e10"),  # YAML 1.1: a string, not a float
        ("set", "/t/empty", "[]"),
        ("set", "/t/u", "h\u00e9llo"),
        ("set", "-v", "/t/angle", "deg(90)"),
        ("set", "-v", "-t", str(files / "text.txt"), "/t/txt"),
        ("set", "/t/dd", "{a: 1}"),
        ("set", "/t/dd", "{b: 2}"),  # an update: /t/dd/a stays
        ("set", "/t/nothing", "{}"),  # sets nothing
    ]
    gets: list[Command] = []
    names = [
        "i",
        "f",
        "small",
        "b",
        "s",
        "n",
        "e",
        "l",
        "d",
        "neg",
        "word",
        "empty",
        "u",
        "angle",
        "txt",
        "dd",
        "d/m",
        "nothing",
    ]
    for name in [*names, ""]:
        gets += [("get", f"/t/{name}"), ("get", "-p", f"/t/{name}")]
    rest: list[Command] = [
        ("get", "-v", "/t/i"),
        ("list", "/t"),
        ("list", "/t/d"),
        ("list", "/t/i"),
        ("list", "/nope"),
        ("set", "-v", "-b", str(files / "data.bin"), "/bin/x"),
        ("list", "/bin"),
        ("delete", "-v", "/bin"),
        ("load", "-v", p, "/lo"),
        ("load", "-", "/stdin"),
        ("get", "/stdin"),
        ("list", "/lo"),
        ("dump", "-v", "", "/lo"),
        ("dump", "-v", str(files / "out.yaml"), "/lo"),
        ("get", "-p", "/lo"),
        ("delete", "-v", "/lo/nest"),
        ("list", "/lo"),
        ("delete", "/lo"),
        ("list", "/lo"),
        ("get", "/t/missing"),
        ("delete", "/t/missing"),
    ]
    return values + gets + rest


STDIN = "q: 1\nr: [a, b]\n"
"""What ``load -`` reads."""


def _files(where: Path) -> Path:
    where.mkdir()
    (where / "params.yaml").write_text(PARAMS_YAML)
    (where / "text.txt").write_text("text\nfile\n")
    (where / "data.bin").write_bytes(b"ab\x00\xff")
    return where


def _outcome(code: int, out: str, files: Path) -> str:
    dumped = files / "out.yaml"
    extra = dumped.read_text() if dumped.exists() else ""
    dumped.unlink(missing_ok=True)
    return f"[{code}]\n{out}{extra}"


@pytest.fixture(scope="module")
def roscore() -> Iterator[Master]:
    reason = missing_oracle()
    if reason is None and not ROSPARAM.is_file():
        reason = f"{ROSPARAM} is not installed"
    if reason is not None:
        pytest.skip(reason)
    with master() as core:
        yield core


GRAPH = """
import sys
from belvedere.graph import Graph, ZenohTransport
g = Graph(sim_time=False, transport=ZenohTransport(endpoint=sys.argv[1]))
g.start(rtf=None)
print("READY", flush=True)
sys.stdin.read()
g.shutdown()
"""


@pytest.fixture
def graph(endpoint: str) -> Iterator[None]:
    """A graph process that holds parameters, as roscore does, on the test's endpoint."""
    proc = subprocess.Popen(
        [sys.executable, "-c", GRAPH, endpoint],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout is not None
    assert proc.stdin is not None
    assert proc.stdout.readline().strip() == "READY"
    yield
    proc.stdin.close()
    proc.wait(timeout=DEADLINE)


def test_rosparam_and_belvedere_param_print_the_same(
    roscore: Master,
    graph: None,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    commands = _commands(_files(tmp_path / "files"))
    expected = []
    for line in commands:
        done = subprocess.run(
            [str(ROSPARAM), *line],
            env=roscore.env,
            input=STDIN if "-" in line else None,
            capture_output=True,
            text=True,
            timeout=DEADLINE,
            check=False,
        )
        assert "Traceback" not in done.stderr, (line, done.stderr)
        expected.append(_outcome(done.returncode, done.stdout, tmp_path / "files"))
    got = []
    for line in commands:
        monkeypatch.setattr(sys, "stdin", io.StringIO(STDIN))
        capsys.readouterr()
        code = main(["param", *line])
        got.append(_outcome(code, capsys.readouterr().out, tmp_path / "files"))
    for line, want, have in zip(commands, expected, got, strict=True):
        assert have.split("\n") == want.split("\n"), line
    # what the comparison establishes, spelt out
    at = dict(zip(commands, expected, strict=True))
    assert at[("get", "/t/n")] == "[0]\n'42'\n\n"
    assert at[("get", "-p", "/t/n")] == "[0]\n42\n"
    assert at[("get", "/t/missing")] == "[1]\n"
    assert at[("list", "/t/i")] == "[0]\n\n"


def test_a_binary_value_is_bytes_and_prints_as_rosparam_meant(
    graph: None, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """What Debian's rosparam fails on (its ``!!binary`` representer writes bytes where
    PyYAML wants text): belvedere writes the one base64 line it meant."""
    data = tmp_path / "data.bin"
    data.write_bytes(b"ab\x00\xff")
    assert main(["param", "set", "-b", str(data), "/bin"]) == 0
    capsys.readouterr()
    assert main(["param", "get", "/bin"]) == 0
    assert capsys.readouterr().out == "!!binary |-\n  YWIA/w==\n\n"
    assert main(["param", "set", "/nul", "~"]) == 1  # the parameter server has no null
    assert "no null value" in capsys.readouterr().err
