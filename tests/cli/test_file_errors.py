"""A file that cannot be read or expanded: ``check`` prints xacro's error exactly as
``belvedere xacro`` does (macro trail, hint), and every verb taking a file says when it is
missing."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from belvedere.cli import main
from tests.conftest import EXAMPLES
from tests.fuzz._mutate import run_bounded

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
BROKEN = {
    "property": (
        f'<robot name="r" {NS}>\n'
        '  <xacro:property name="wheel_radius" value="0.1"/>\n'
        '  <xacro:macro name="wheel" params="side">\n'
        '    <link name="${side}_wheel"><visual><geometry>\n'
        '      <cylinder radius="${wheel_raduis}" length="0.02"/>\n'
        "    </geometry></visual></link>\n"
        "  </xacro:macro>\n"
        '  <link name="base"/>\n'
        '  <xacro:wheel side="left"/>\n'
        "</robot>\n",
        "{f}:5:25: error: name 'wheel_raduis' is not defined when evaluating expression "
        "'wheel_raduis'\n"
        "  in macro 'wheel' called from {f}:9:3\n"
        "  hint: did you mean 'wheel_radius'?\n",
    ),
    "macro": (
        f'<robot name="r" {NS}>\n'
        '  <xacro:macro name="caster" params=""><link name="c"/></xacro:macro>\n'
        "  <xacro:castor/>\n"
        "</robot>\n",
        "{f}:3:3: error: unknown macro name: xacro:castor\n  hint: did you mean xacro:caster?\n",
    ),
    "include": (
        f'<robot name="r" {NS}>\n  <xacro:include filename="parts.xacro"/>\n</robot>\n',
        "{f}:2:3: error: cannot include {d}/parts.xacro: no such file\n",
    ),
}


@pytest.mark.parametrize("case", BROKEN)
def test_check_prints_xacros_error_as_xacro_does(
    case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text, expected = BROKEN[case]
    path = tmp_path / "robot.xacro"
    path.write_text(text)
    message = expected.format(f=path, d=tmp_path)
    assert main(["xacro", str(path)]) == 1
    assert capsys.readouterr().err == message
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr()
    assert out.err == message
    assert out.out == ""


def test_check_json_keeps_the_trail_and_hint(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "robot.xacro"
    path.write_text(BROKEN["property"][0])
    assert main(["check", "--json", str(path)]) == 1
    [diagnostic] = json.loads(capsys.readouterr().out)["diagnostics"]
    assert diagnostic["line"] == 5
    assert diagnostic["trail"] == [f"in macro 'wheel' called from {path}:9:3"]
    assert diagnostic["hint"] == "did you mean 'wheel_radius'?"


MBOT = EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["xacro", "{m}"], "error: cannot read {m}: No such file or directory\n"),
        (["check", "{m}"], "error: cannot read {m}: No such file or directory\n"),
        (["display", "{m}", "--port", "0"], "error: cannot read {m}: No such file or directory\n"),
        (["sim", "{m}", "--headless"], "error: cannot read {m}: No such file or directory\n"),
        (
            ["launch", "{l}"],
            "error: launch file '{l}' does not exist\n"
            "  hint: or give a package and a file: launch PKG FILE\n",
        ),
        (
            ["sim", str(MBOT), "--engine", "physics", "--world", "{w}", "--headless"],
            "error: cannot read {w}: No such file or directory\n",
        ),
        (
            ["sim", str(MBOT), "--config", "{y}", "--headless"],
            "error: cannot read YAML file '{y}': No such file or directory\n",
        ),
        (
            ["display", str(MBOT), "--rviz", "{r}", "--port", "0"],
            "error: cannot read rviz config {r}: No such file or directory\n",
        ),
    ],
    ids=["xacro", "check", "display", "sim", "launch", "world", "config", "rviz"],
)
def test_a_missing_file_is_named_as_missing(
    endpoint: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    args: list[str],
    message: str,
) -> None:
    names = _files(tmp_path, "nothere")
    argv = _argv(args, names)
    assert main(["-q", *argv]) == 1
    err = capsys.readouterr().err
    assert err.endswith(message.format(**names))
    assert "Traceback" not in err


def _files(tmp_path: Path, stem: str) -> dict[str, Path]:
    """The files a case's arguments name by letter: {m} a model, {l} a launch file, {w} a
    world, {y} a YAML file, {r} an rviz config."""
    return {
        k: tmp_path / f"{stem}.{ext}"
        for k, ext in zip("mlwyr", ("xacro", "launch", "world", "yaml", "rviz"), strict=True)
    }


def _argv(args: list[str], names: dict[str, Path]) -> list[str]:
    argv = [a.format(**names) for a in args]
    if args[0] in ("sim", "display"):
        argv += ["--duration", "0.1"]  # should it get that far
    return argv


FIFO = ": it is a FIFO (named pipe), not a regular file\n"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["xacro", "{m}"], "error: cannot read {m}" + FIFO),
        (["check", "{m}"], "error: cannot read {m}" + FIFO),
        (["display", "{m}", "--port", "0"], "error: cannot read {m}" + FIFO),
        (["sim", "{m}", "--headless"], "error: cannot read {m}" + FIFO),
        (["launch", "{l}"], "error: cannot read {l}" + FIFO),
        (
            ["sim", str(MBOT), "--engine", "physics", "--world", "{w}", "--headless"],
            "error: cannot read {w}" + FIFO,
        ),
        (
            ["sim", str(MBOT), "--config", "{y}", "--headless"],
            "error: cannot read YAML file '{y}'" + FIFO,
        ),
        (
            ["display", str(MBOT), "--rviz", "{r}", "--port", "0"],
            "error: cannot read rviz config {r}" + FIFO,
        ),
        (["map", "show", "{y}"], "error: cannot read the map file '{y}'" + FIFO),
    ],
    ids=["xacro", "check", "display", "sim", "launch", "world", "config", "rviz", "map"],
)
def test_a_fifo_is_refused_not_waited_on(
    endpoint: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    args: list[str],
    message: str,
) -> None:
    names = _files(tmp_path, "fifo")
    for path in names.values():
        os.mkfifo(path)
    argv = _argv(args, names)
    with run_bounded(120):  # a reader that waits for a writer fails here, not the suite
        assert main(["-q", *argv]) == 1
    err = capsys.readouterr().err
    assert err.endswith(message.format(**names))
    assert "Traceback" not in err
