"""``belvedere roscore``: the URI it prints serves Debian's tools; a port in use is one error;
off loopback it warns that ROS 1 has no authentication."""

from __future__ import annotations

import subprocess
import sys

import pytest

from belvedere.cli.roscore import _loopback
from tests.conftest import free_port
from tests.ros1wire.conftest import Ros1
from tests.waiting import DEADLINE


def _roscore(port: int, *more: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "belvedere", "roscore", "-p", str(port), *more],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def test_roscore_prints_its_uri_and_a_taken_port_is_one_error(needs_debian_ros: None) -> None:
    port = free_port()
    first = _roscore(port, "--duration", "30")
    try:
        assert first.stdout is not None
        line = first.stdout.readline().strip()
        assert line == f"ROS_MASTER_URI=http://127.0.0.1:{port}/"
        ros = Ros1(line.partition("=")[2])
        assert ros.run("rosparam", "set", "/greeting", "hello").returncode == 0
        assert ros.run("rosparam", "get", "/greeting").stdout == "hello\n"
        second = _roscore(port, "--duration", "1")
        _, err = second.communicate(timeout=DEADLINE)
        assert second.returncode == 1
        errors = [e for e in err.splitlines() if e.startswith("error:")]
        assert errors == [
            f"error: cannot serve a master on 127.0.0.1:{port}: Address already in use "
            "(is another roscore running? `-p PORT` chooses another port)"
        ], err
    finally:
        first.terminate()
        first.wait(timeout=DEADLINE)


@pytest.mark.parametrize(
    ("host", "loopback"),
    [
        ("127.0.0.1", True),
        ("127.0.0.2", True),
        ("localhost", True),
        ("::1", True),
        ("0.0.0.0", False),
        ("192.168.1.5", False),
        ("robot.local", False),
    ],
)
def test_only_loopback_addresses_are_quiet(host: str, loopback: bool) -> None:
    assert _loopback(host) is loopback
