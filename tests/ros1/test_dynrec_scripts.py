"""The dynamic_tutorials package as the course runs it: ``server.py`` and ``client.py`` as
processes of their own on this test's graph, and ``dynparam`` against the server."""

from __future__ import annotations

import ast
import contextlib
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

import pytest

from tests.conftest import DATA, EXAMPLES
from tests.waiting import DEADLINE, wait_until

RUN = [sys.executable, "-m", "belvedere", "run", "--headless"]
SCRIPTS = EXAMPLES / "dynamic_tutorials" / "scripts"


class Lines:
    """What a process has printed so far (its stderr and stdout, read as they come)."""

    def __init__(self, stream: IO[str]) -> None:
        import threading

        self.lines: list[str] = []
        self._thread = threading.Thread(target=self._read, args=(stream,), daemon=True)
        self._thread.start()

    def _read(self, stream: IO[str]) -> None:
        for line in stream:
            self.lines.append(line.rstrip("\n"))

    def requests(self) -> list[str]:
        return [line.split("Request: ", 1)[1] for line in self.lines if "Request: " in line]


@contextlib.contextmanager
def running(script: str, *args: str) -> Iterator[Lines]:
    """One of the package's scripts run by ``belvedere run``, stopped at the end."""
    process = subprocess.Popen(
        [*RUN, str(SCRIPTS / script), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    assert process.stdout is not None
    try:
        yield Lines(process.stdout)
    finally:
        process.terminate()
        process.wait(DEADLINE)


@pytest.fixture
def server(endpoint: str) -> Iterator[Lines]:
    with running("server.py") as out:
        wait_until(out.requests, what="the server's first callback", detail=lambda: out.lines)
        yield out


def run_dynparam(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*RUN, "dynamic_reconfigure", "dynparam", *args],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )


def dynparam(*args: str) -> str:
    ran = run_dynparam(*args)
    assert ran.returncode == 0, ran.stderr
    return ran.stdout


def _config(text: str) -> dict[str, Any]:
    value = ast.literal_eval(text.strip())
    assert isinstance(value, dict)
    return value


def _request(text: str) -> list[str]:
    return [part.strip() for part in text.split(",")]


def test_dynparam_gets_sets_and_lists(server: Lines, tmp_path: Path) -> None:
    assert _request(server.requests()[0]) == ["50", "0.5", "Hello World", "True", "1"]
    got = _config(dynparam("get", "/dynamic_tutorials"))
    assert {k: v for k, v in got.items() if k != "groups"} == {
        "bool_param": True,
        "int_param": 50,
        "size": 1,
        "str_param": "Hello World",
        "double_param": 0.5,
    }
    assert got["groups"]["name"] == "Default"
    assert got["groups"]["int_param"] == 50
    assert dynparam("list").split() == ["/dynamic_tutorials"]

    # clamped to the range, an enum constant by name, a bool from text: as ROS's client does
    dynparam("set", "/dynamic_tutorials", "{int_param: 300, size: Large, bool_param: 'no'}")
    wait_until(lambda: len(server.requests()) > 1, what="the server's second callback")
    assert _request(server.requests()[1]) == ["100", "0.5", "Hello World", "False", "2"]
    dynparam("set", "/dynamic_tutorials", "double_param", "-3")
    after = _config(dynparam("get", "/dynamic_tutorials"))
    assert after["double_param"] == 0.0
    assert after["int_param"] == 100

    dump = tmp_path / "tutorials.yaml"
    dynparam("dump", "/dynamic_tutorials", str(dump))
    dump.write_text(dump.read_text().replace("str_param: Hello World", "str_param: loaded"))
    dynparam("load", "/dynamic_tutorials", str(dump))
    assert _config(dynparam("get", "/dynamic_tutorials"))["str_param"] == "loaded"

    # a file ROS's dynparam dumped: its Config objects read as mappings, nothing constructed
    ros_dump = tmp_path / "ros.yaml"
    ros_dump.write_text(
        "!!python/object/new:dynamic_reconfigure.encoding.Config\n"
        "dictitems:\n  int_param: 7\n  groups: !!python/object/new:"
        "dynamic_reconfigure.encoding.Config\n    dictitems: {id: 0}\n    state: []\n"
        "state: []\n"
    )
    dynparam("load", "/dynamic_tutorials", str(ros_dump))
    assert _config(dynparam("get", "/dynamic_tutorials"))["int_param"] == 7
    hostile = tmp_path / "hostile.yaml"
    hostile.write_text("!!python/object/apply:os.system ['touch /tmp/dynparam_was_here']\n")
    refused = run_dynparam("load", "/dynamic_tutorials", str(hostile))
    assert refused.returncode == 1
    assert f"error: cannot load {hostile}" in refused.stderr

    unknown = run_dynparam("set", "/dynamic_tutorials", "speed", "1")
    assert "error updating parameters: don't know parameter: speed" in unknown.stdout


def test_the_tutorial_client_reconfigures_the_server(server: Lines) -> None:
    with running("client.py") as out:
        # the first update: int_param 1, double_param 1/2, its time as str_param, bool_param True
        wait_until(
            lambda: len(server.requests()) > 1, what="the client's update", detail=lambda: out.lines
        )
        first = _request(server.requests()[1])
        assert first[:2] == ["1", "0.5"]
        assert first[3:] == ["True", "1"]
        wait_until(
            lambda: any("Config set to 1, 0.5" in line for line in out.lines),
            what="the client's config_callback",
            detail=lambda: out.lines,
        )


def test_a_script_importing_a_cfg_that_imports_os_fails_at_its_line(endpoint: str) -> None:
    package = DATA / "dynrec" / "sneaky_cfg"
    ran = subprocess.run(
        [*RUN, str(package / "scripts" / "use.py")],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )
    assert ran.returncode == 1
    cfg = package / "cfg" / "Sneaky.cfg"
    assert f"ImportError: {cfg}:5:1: error: a .cfg may not import os" in ran.stderr
    assert not Path("/tmp/sneaky_cfg_was_here").exists()


def test_dynparam_without_a_server_is_one_error_after_its_timeout(endpoint: str) -> None:
    ran = run_dynparam("get", "-t", "0.5", "/nobody")
    assert ran.returncode == 1
    assert "error: timeout exceeded while waiting for service /nobody/set_parameters" in ran.stderr
    assert "Traceback" not in ran.stderr


def test_the_server_starts_from_its_private_parameters_clamped(endpoint: str) -> None:
    with running("server.py", "_int_param:=500", "_str_param:=from the command line") as out:
        wait_until(out.requests, what="the server's first callback", detail=lambda: out.lines)
        assert _request(out.requests()[0]) == ["100", "0.5", "from the command line", "True", "1"]
        ran = subprocess.run(
            [sys.executable, "-m", "belvedere", "param", "get", "/dynamic_tutorials/int_param"],
            capture_output=True,
            text=True,
            timeout=DEADLINE,
            check=False,
        )
        assert ran.stdout.strip() == "100"  # written back, clamped, as ROS's server does
