"""``belvedere teleop`` in a real (pseudo-)terminal, publishing to another process's graph."""

from __future__ import annotations

import os
import pty
import select
import subprocess
import sys
import termios
import time
from typing import Any

import pytest

from belvedere.graph import Graph, ZenohTransport
from tests.waiting import DEADLINE, wait_until


def _read_until(fd: int, text: str, timeout: float = DEADLINE) -> str:
    seen = ""
    deadline = time.monotonic() + timeout
    while text not in seen:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            msg = f"never saw {text!r}; got {seen!r}"
            raise AssertionError(msg)
        ready, _, _ = select.select([fd], [], [], remaining)
        if ready:
            try:
                seen += os.read(fd, 4096).decode(errors="replace")
            except OSError:  # the child closed the terminal
                break
    return seen


def _wait(got: list[Any], count: int) -> None:
    wait_until(
        lambda: len(got) >= count, what=f"{count} messages on /cmd_vel", detail=lambda: len(got)
    )


@pytest.mark.parametrize("layout", ["twist_keyboard", "mbot"])
def test_drive_from_a_pseudo_terminal(endpoint: str, layout: str) -> None:
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
    got: list[Any] = []
    graph.create_node("robot").subscribe("/cmd_vel", "geometry_msgs/Twist", got.append)
    graph.start(rtf=None)
    master, slave = pty.openpty()
    before = termios.tcgetattr(slave)
    proc = subprocess.Popen(
        [sys.executable, "-m", "belvedere", "teleop", "--layout", layout],
        stdin=slave,
        stdout=slave,
        stderr=slave,
        close_fds=True,
    )
    try:
        banner = "Reading from the keyboard" if layout == "twist_keyboard" else "Control mbot!"
        _read_until(master, banner)
        assert termios.tcgetattr(slave)[3] & termios.ICANON == 0  # raw mode
        if layout == "twist_keyboard":
            os.write(master, b"i")
            _wait(got, 1)
            assert (got[-1].linear.x, got[-1].angular.z) == (0.5, 0.0)
            os.write(master, b"q")
            _read_until(master, "currently:\tspeed 0.55\tturn 1.1")
            os.write(master, b"L")
            _wait(got, 3)
            assert got[-1].linear.y == pytest.approx(-0.55)
            os.write(master, b"k")
            _wait(got, 4)
            assert got[-1].linear.y == 0.0
        else:
            os.write(master, b"i")
            _wait(got, 6)  # published every 0.1 s, ramping up by 0.02 m/s
            ramp = [m.linear.x for m in got[:6]]
            assert ramp[:4] == pytest.approx([0.02, 0.04, 0.06, 0.08])
        count = len(got)
        os.write(master, b"\x03")
        assert proc.wait(timeout=DEADLINE) == 0
        _wait(got, count + 1)
        assert (got[-1].linear.x, got[-1].linear.y, got[-1].angular.z) == (0.0, 0.0, 0.0)
        assert termios.tcgetattr(slave) == before  # the terminal is restored
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(master)
        os.close(slave)
        graph.shutdown()


def test_not_a_terminal_is_a_clear_error(endpoint: str) -> None:
    result = subprocess.run(
        [sys.executable, "-m", "belvedere", "teleop"],
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )
    assert result.returncode == 1
    assert "error: teleop reads keys from a terminal" in result.stderr
    assert "Traceback" not in result.stderr
