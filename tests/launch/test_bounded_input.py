"""Launch files from the internet: commands that print or run forever, files that are not
files (FIFOs, devices, directories), text that is not UTF-8 — each one error at its line."""

from __future__ import annotations

import os
import shlex
import sys
from pathlib import Path

import pytest

from belvedere import bounded
from belvedere.errors import ParseError
from belvedere.launch import LaunchError, load_launch
from belvedere.launch._model import LaunchConfig
from belvedere.packages import PackageIndex
from tests.waiting import wait_until


def _load(tmp_path: Path, body: str) -> LaunchConfig:
    path = tmp_path / "robot.launch"
    path.write_text(f"<launch>\n  {body}\n</launch>\n")
    return load_launch(path, packages=PackageIndex([]))


def _python(code: str) -> str:
    """A ``<param command>`` that runs ``code`` in Python (XML-escaped for an attribute)."""
    command = shlex.join([sys.executable, "-c", code])
    return command.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


def test_a_command_that_never_stops_printing_is_stopped_at_the_cap(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(bounded, "COMMAND_OUTPUT_BYTES", 4096)
    forever = _python("while True: print('y' * 1000)")
    with pytest.raises(
        LaunchError,
        match=r"robot\.launch:2:3: error: command .* printed more than 4 KiB on stdout",
    ):
        _load(tmp_path, f'<param name="x" command="{forever}"/>')


def test_a_flood_on_stderr_is_stopped_too(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(bounded, "COMMAND_OUTPUT_BYTES", 4096)
    forever = _python("while True: print('y' * 1000, file=__import__('sys').stderr)")
    with pytest.raises(LaunchError, match=r"robot\.launch:2:3: .* more than 4 KiB on stderr"):
        _load(tmp_path, f'<param name="x" command="{forever}"/>')


def test_a_command_that_does_not_end_is_stopped_with_what_it_started(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(bounded, "COMMAND_SECONDS", 1.0)
    marker = tmp_path / "child.pid"
    # a shell whose child sleeps: the child is in the command's process group, and goes too
    command = f"sh -c 'sleep 600 &amp; echo $! &gt; {marker}; wait'"
    with pytest.raises(LaunchError, match=r"robot\.launch:2:3: .* did not end within 1 s"):
        _load(tmp_path, f'<param name="x" command="{command}"/>')
    if not marker.exists():  # a machine too busy to start the shell within the second
        pytest.skip("the command's shell did not start its child in time")
    pid = int(marker.read_text())
    wait_until(lambda: not _alive(pid), what="the command's child to be killed", timeout=30)


def _alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie waiting to be reaped does not)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except FileNotFoundError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def test_output_that_is_not_utf8_is_refused_as_roslaunch_refuses_it(tmp_path: Path) -> None:
    command = _python("import sys; sys.stdout.buffer.write(b'ok\\xff')")
    with pytest.raises(
        LaunchError, match=r"robot\.launch:2:3: .* bytes that are not UTF-8 \(0xff at byte 2\)"
    ):
        _load(tmp_path, f'<param name="x" command="{command}"/>')


def test_a_failing_command_shows_the_end_of_its_stderr(tmp_path: Path) -> None:
    command = _python("import sys; sys.stderr.write('x' * 100000 + 'the end'); sys.exit(3)")
    with pytest.raises(LaunchError, match=r"failed \(exit 3\): …x+the end$"):
        _load(tmp_path, f'<param name="x" command="{command}"/>')


def test_a_command_output_is_the_param(tmp_path: Path) -> None:
    config = _load(tmp_path, f'<param name="x" command="{_python("print(42)")}"/>')
    assert config.params["/x"].value == 42


@pytest.mark.parametrize(
    ("attribute", "kind"),
    [
        ('<rosparam file="{fifo}"/>', "YAML file '.*gains\\.yaml': it is a FIFO"),
        ('<rosparam file="{fifo}" subst_value="true"/>', "'.*gains\\.yaml': it is a FIFO"),
        ('<param name="x" textfile="{fifo}"/>', "textfile '.*gains\\.yaml': it is a FIFO"),
        ('<param name="x" binfile="{fifo}"/>', "binfile '.*gains\\.yaml': it is a FIFO"),
        ('<param name="x" textfile="/dev/zero"/>', "'/dev/zero': it is a character device"),
        ('<param name="x" binfile="{dir}"/>', "it is a directory, not a regular file"),
        ('<include file="{fifo}"/>', "gains\\.yaml: it is a FIFO"),
    ],
)
def test_files_that_are_not_regular_files_are_refused_at_their_line(
    tmp_path: Path, attribute: str, kind: str
) -> None:
    fifo = tmp_path / "gains.yaml"
    os.mkfifo(fifo)
    body = attribute.format(fifo=fifo, dir=tmp_path)
    with pytest.raises(ParseError, match=rf"robot\.launch:2:3: error: cannot read .*{kind}"):
        _load(tmp_path, body)


def test_a_yaml_file_past_the_cap_is_refused_unread(tmp_path: Path) -> None:
    big = tmp_path / "big.yaml"
    big.write_bytes(b"a: 1\n" + b"#" * bounded.YAML_TEXT_BYTES)
    with pytest.raises(ParseError, match=r"robot\.launch:2:3: .* more than the 4 MiB"):
        _load(tmp_path, f'<rosparam file="{big}"/>')


@pytest.mark.parametrize("subst", ["false", "true"])
def test_a_yaml_file_that_is_not_utf8_is_refused_at_its_byte(tmp_path: Path, subst: str) -> None:
    bad = tmp_path / "gains.yaml"
    bad.write_bytes(b"a: 1\nb: \xff\n")
    with pytest.raises(
        ParseError, match=r"gains\.yaml:2:4: error: .* not UTF-8 text \(byte 0xff\)"
    ):
        _load(tmp_path, f'<rosparam file="{bad}" subst_value="{subst}"/>')
