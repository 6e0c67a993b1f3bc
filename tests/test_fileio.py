"""Every file belvedere writes is written whole or not at all, and no user file is lost."""

from __future__ import annotations

import errno
import os
import signal
import stat
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from belvedere.fileio import (
    TEMP_MARKER,
    FileWriteError,
    backup_file,
    stage_write,
    write_file,
)


def temps(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if TEMP_MARKER in p.name)


def mode(path: Path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


@pytest.fixture
def umask_022() -> Iterator[None]:
    old = os.umask(0o022)
    try:
        yield
    finally:
        os.umask(old)


@pytest.mark.usefixtures("umask_022")
def test_a_new_file_gets_the_permissions_of_any_new_file(tmp_path: Path) -> None:
    out = write_file(tmp_path / "robot.urdf", "<robot/>\n")
    assert out == tmp_path / "robot.urdf"
    assert out.read_text() == "<robot/>\n"
    assert mode(out) == 0o644  # 0666 less the umask, not a temporary file's 0600
    assert temps(tmp_path) == []


@pytest.mark.parametrize("perm", [0o644, 0o640, 0o755])
def test_replacing_keeps_the_targets_permissions(tmp_path: Path, perm: int) -> None:
    target = tmp_path / "params.yaml"
    target.write_text("old: 1\n")
    target.chmod(perm)
    write_file(target, "new: 2\n")
    assert target.read_text() == "new: 2\n"
    assert mode(target) == perm


def test_a_symlink_stays_a_link_and_its_file_is_written(tmp_path: Path) -> None:
    real = tmp_path / "real"
    real.mkdir()
    (real / "robot.xacro").write_text("old")
    link = tmp_path / "robot.xacro"
    link.symlink_to(real / "robot.xacro")
    assert write_file(link, "new") == real / "robot.xacro"
    assert link.is_symlink()
    assert (real / "robot.xacro").read_text() == "new"
    assert temps(tmp_path) == []
    assert temps(real) == []


def test_make_dirs_creates_the_directory(tmp_path: Path) -> None:
    out = tmp_path / "a" / "b" / "robot.urdf"
    write_file(out, b"\x00\x01", make_dirs=True)
    assert out.read_bytes() == b"\x00\x01"


def test_a_directory_is_not_replaced(tmp_path: Path) -> None:
    target = tmp_path / "out"
    target.mkdir()
    with pytest.raises(FileWriteError, match=r"cannot write .*out: Is a directory; .*out is "):
        write_file(target, "x")
    assert target.is_dir()
    assert temps(tmp_path) == []


def test_an_error_at_write_changes_nothing_and_leaves_no_temporary_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "robot.urdf"
    target.write_text("the user's file")

    def no_space(fd: int, data: object) -> int:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "write", no_space)
    with pytest.raises(
        FileWriteError,
        match=r"^error: cannot write .*robot\.urdf: No space left on device; "
        r".*robot\.urdf is unchanged$",
    ):
        write_file(target, "new")
    with pytest.raises(FileWriteError, match=r"new\.urdf: No space left on device; nothing was"):
        write_file(tmp_path / "new.urdf", "new")
    monkeypatch.undo()
    assert target.read_text() == "the user's file"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["robot.urdf"]


def test_an_error_at_fsync_changes_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "robot.urdf"
    target.write_text("the user's file")

    def io_error(fd: int) -> None:
        raise OSError(errno.EIO, os.strerror(errno.EIO))

    monkeypatch.setattr(os, "fsync", io_error)
    with pytest.raises(FileWriteError, match=r"robot\.urdf: Input/output error"):
        write_file(target, "new")
    monkeypatch.undo()
    assert target.read_text() == "the user's file"
    assert temps(tmp_path) == []


def test_a_full_file_system(full_disk: Path) -> None:
    target = full_disk / "robot.urdf"
    target.write_text("the user's file")
    big = "x" * (1 << 20)
    with pytest.raises(FileWriteError, match=r"robot\.urdf: No space left on device; .* unchanged"):
        write_file(target, big)
    with pytest.raises(FileWriteError, match=r"other\.urdf: No space left on device; nothing was"):
        write_file(full_disk / "other.urdf", big)
    assert target.read_text() == "the user's file"
    assert sorted(p.name for p in full_disk.iterdir()) == ["robot.urdf"]
    # The space came back: a small write still works.
    write_file(target, "small")
    assert target.read_text() == "small"


def test_a_backup_never_replaces_an_existing_file(tmp_path: Path) -> None:
    target = tmp_path / "robot.xacro"
    target.write_text("version 1")
    target.chmod(0o640)
    os.utime(target, (1_000_000_000, 1_000_000_000))
    notes = tmp_path / "robot.xacro.orig"
    notes.write_text("the user's own notes")
    first = backup_file(target)
    target.write_text("version 2")
    second = backup_file(target)
    assert (first.name, second.name) == ("robot.xacro.orig.1", "robot.xacro.orig.2")
    assert notes.read_text() == "the user's own notes"
    assert first.read_text() == "version 1"
    assert second.read_text() == "version 2"
    assert mode(first) == 0o640
    assert first.stat().st_mtime == 1_000_000_000  # a copy, as cp -p makes
    assert temps(tmp_path) == []


def test_a_backup_of_a_link_sits_beside_the_real_file(tmp_path: Path) -> None:
    real = tmp_path / "pkg" / "robot.xacro"
    real.parent.mkdir()
    real.write_text("data")
    link = tmp_path / "robot.xacro"
    link.symlink_to(real)
    assert backup_file(link) == real.with_name("robot.xacro.orig")


def test_a_failed_backup_leaves_nothing(full_disk: Path) -> None:
    target = full_disk / "robot.xacro"
    target.write_text("y" * 40_000)  # a second copy does not fit in 64 KiB
    with pytest.raises(FileWriteError, match=r"robot\.xacro\.orig: No space left on device"):
        backup_file(target)
    assert sorted(p.name for p in full_disk.iterdir()) == ["robot.xacro"]


def test_a_writer_at_work_keeps_its_temporary_file(tmp_path: Path) -> None:
    target = tmp_path / "map.yaml"
    staged = stage_write(target, "first")
    [temp] = temps(tmp_path)
    write_file(target, "second")  # meanwhile, another write to the same file
    assert temps(tmp_path) == [temp]
    staged.commit()
    assert target.read_text() == "first"
    assert temps(tmp_path) == []


WRITER = """
import sys
from belvedere.fileio import stage_write, write_file
target, how = sys.argv[1], sys.argv[2]
big = [b"A" * (8 << 20), b"B" * (8 << 20)]
if how == "staged":
    stage_write(target, big[0])
    print("STAGED", flush=True)
    sys.stdin.read()
else:
    print("WRITING", flush=True)
    n = 0
    while True:
        write_file(target, big[n % 2])
        n += 1
"""


def _writer(tmp_path: Path, target: Path, how: str, expect: str) -> subprocess.Popen[str]:
    script = tmp_path / "writer.py"
    script.write_text(WRITER)
    proc = subprocess.Popen(
        [sys.executable, str(script), str(target), how],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout is not None
    assert proc.stdout.readline().strip() == expect
    return proc


def test_kill_9_after_the_data_is_written_leaves_the_old_file(tmp_path: Path) -> None:
    target = tmp_path / "world.yaml"
    target.write_text("old")
    proc = _writer(tmp_path, target, "staged", "STAGED")
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=10)
    assert target.read_text() == "old"
    [stale] = temps(tmp_path)
    assert stale.startswith(f".world.yaml{TEMP_MARKER}")
    # The next write to the file removes what the killed writer left.
    write_file(target, "new")
    assert target.read_text() == "new"
    assert temps(tmp_path) == []


def test_kill_9_during_writes_never_leaves_a_partial_file(tmp_path: Path) -> None:
    target = tmp_path / "dump.bin"
    proc = _writer(tmp_path, target, "loop", "WRITING")
    # Wait until at least one write is in place and the next one is under way.
    while not (target.exists() and temps(tmp_path)):
        assert proc.poll() is None
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=10)
    data = target.read_bytes()
    assert data in (b"A" * (8 << 20), b"B" * (8 << 20))
    write_file(target, "next")
    assert temps(tmp_path) == []
