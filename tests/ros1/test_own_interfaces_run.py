"""The course's packages with interfaces of their own, run as a learner runs them: each script
a process of its own (``belvedere run``) on this test's graph, its types read from the
package's msg/, srv/ and action/ files with no build step."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]


class Running:
    """A process whose output lines are collected as they come."""

    def __init__(self, argv: list[str], *, cwd: Path, env: dict[str, str]) -> None:
        self.lines: list[str] = []
        self.process = subprocess.Popen(
            argv,
            cwd=cwd,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,  # its script is its child: both end together
        )
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            self.lines.append(line.rstrip("\n"))

    def wait_for(self, text: str) -> str:
        def seen() -> str:
            return next((line for line in self.lines if text in line), "")

        return wait_until(seen, what=f"{text!r} in the output", detail=lambda: self.lines[-5:])

    def stop(self) -> None:
        if self.process.poll() is None:
            os.killpg(self.process.pid, signal.SIGINT)  # as Ctrl-C in its terminal
        self.process.wait(timeout=DEADLINE)
        self._reader.join(timeout=DEADLINE)


@pytest.fixture
def processes() -> Iterator[list[Running]]:
    started: list[Running] = []
    yield started
    for run in reversed(started):
        run.stop()


def _env(package_path: Path | None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_PACKAGE_PATH",)}
    if package_path is not None:
        env["ROS_PACKAGE_PATH"] = str(package_path)
    return env


def _finished(argv: list[str], *, cwd: Path, env: dict[str, str]) -> str:
    """The output of a command that must succeed."""
    done = subprocess.run(
        argv, cwd=cwd, env=env, capture_output=True, text=True, timeout=DEADLINE, check=True
    )
    return done.stdout


def test_person_publisher_and_subscriber(processes: list[Running], tmp_path: Path) -> None:
    """As after sourcing the workspace: ROS_PACKAGE_PATH names it; run from elsewhere."""
    env = _env(EXAMPLES)
    for script in ("person_publisher.py", "person_subscriber.py"):
        argv = [*BELVEDERE, "run", "--headless", "learning_topic", script]
        processes.append(Running(argv, cwd=tmp_path, env=env))
        processes[-1].wait_for("Person Info: name:Tom")  # (the first provides the graph)
    processes[1].wait_for("Subscribe Person Info: name:Tom  age:18  sex:male")
    # another terminal's tool, in the package's directory with nothing sourced
    echo = _finished(
        [*BELVEDERE, "topic", "echo", "/person_info", "-n", "1"],
        cwd=EXAMPLES / "learning_topic",
        env=_env(None),
    )
    assert 'name: "Tom"\nage: 18\nsex: 1\n---' in echo


def test_person_server_and_client(processes: list[Running], tmp_path: Path) -> None:
    """Scripts given by their paths: their workspace is the package path."""
    home = EXAMPLES / "learning_service" / "scripts"
    env = _env(None)
    server = Running(
        [*BELVEDERE, "run", "--headless", str(home / "person_server.py")], cwd=tmp_path, env=env
    )
    processes.append(server)
    server.wait_for("Ready to show person information.")
    client = _finished(
        [*BELVEDERE, "run", "--headless", str(home / "person_client.py")], cwd=tmp_path, env=env
    )
    assert "Show person result : OK" in client
    server.wait_for("Person: name:Tom  age:20  sex:1")
    call = _finished(
        [*BELVEDERE, "service", "call", "/show_person", "{name: Ann, age: 3, sex: 2}"],
        cwd=EXAMPLES / "learning_service",
        env=env,
    )
    assert 'result: "OK"' in call
    server.wait_for("Person: name:Ann  age:3  sex:2")


def test_do_dishes_action(processes: list[Running], tmp_path: Path) -> None:
    home = EXAMPLES / "learning_action" / "scripts"
    env = _env(None)
    server = Running(
        [*BELVEDERE, "run", "--headless", str(home / "do_dishes_server.py")], cwd=tmp_path, env=env
    )
    processes.append(server)
    server.wait_for("listening")  # the graph it provides, before a client joins it
    client = _finished(
        [*BELVEDERE, "run", "--headless", str(home / "do_dishes_client.py")], cwd=tmp_path, env=env
    )
    feedback = [line for line in client.splitlines() if line.startswith("Percent")]
    assert feedback == [f"Percent complete: {p:.1f}%" for p in (20, 40, 60, 80, 100)]
    assert "Result: 10 dishes cleaned" in client
    server.wait_for("Dishwasher 1 finished working.")
