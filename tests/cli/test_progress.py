"""Long work shows a progress bar (rich) on a terminal, and none when piped: ``bag play``
(the bag's seconds) and ``slam`` (its scans), run as a user runs them, their stderr a real
pseudo-terminal."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.bags._make import write_sample
from tests.nav.test_hector import _bag
from tests.terminal import Terminal
from tests.waiting import DEADLINE

BAR = "━".encode()


def _on_terminal(args: list[str], cwd: Path) -> bytes:
    terminal = Terminal()
    try:
        proc = subprocess.run(
            [sys.executable, "-m", "belvedere", *args],
            cwd=cwd,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=terminal.slave,
            timeout=DEADLINE,
            check=False,
        )
        assert proc.returncode == 0, terminal.output[-400:]
        terminal.wait_for("100%")
        return terminal.output
    finally:
        terminal.close()


def _piped(args: list[str], cwd: Path) -> bytes:
    proc = subprocess.run(
        [sys.executable, "-m", "belvedere", *args],
        cwd=cwd,
        stdin=subprocess.DEVNULL,
        capture_output=True,
        timeout=DEADLINE,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr[-400:]
    return proc.stderr


def test_bag_play_shows_progress_on_a_terminal(endpoint: str, tmp_path: Path) -> None:
    write_sample(tmp_path / "sample.bag")
    args = ["bag", "play", "sample.bag", "-r", "20"]
    shown = _on_terminal(args, tmp_path)
    assert BAR in shown
    assert BAR not in _piped(args, tmp_path)
    assert BAR not in _piped([*args, "-q"], tmp_path)


def test_slam_shows_progress_on_a_terminal(tmp_path: Path) -> None:
    _bag(tmp_path / "room.bag")
    args = ["slam", "room.bag", "--algorithm", "hector", "--base-frame", "base_footprint"]
    args += ["-o", "map", "map_resolution:=0.05", "map_size:=512"]
    shown = _on_terminal(args, tmp_path)
    assert BAR in shown
    assert b"slam (scans)" in shown
    assert b"map updates" in shown  # the mapper's status beside the bar
    assert BAR not in _piped(args, tmp_path)
