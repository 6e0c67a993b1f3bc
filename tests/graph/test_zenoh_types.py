"""Types over the graph: a terminal with nothing sourced (no package path, run from outside
any workspace) echoes, records and calls what a learner's scripts publish and serve, the
types learnt from the processes that have the package; and answers that lie are refused."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import zenoh

from belvedere.bags import open_bag
from belvedere.errors import BelvedereError
from belvedere.graph import ZenohTransport
from belvedere.graph._zenoh_session import open_session
from belvedere.msgs import MessageTypeError, types
from tests.conftest import EXAMPLES, TEST_DOMAIN
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]


def _bare_env() -> dict[str, str]:
    drop = ("ROS_PACKAGE_PATH", "BELVEDERE_PACKAGE_PATH")
    return {k: v for k, v in os.environ.items() if k not in drop}


class Script:
    """``belvedere run`` of a script, its output lines collected as they come."""

    def __init__(self, argv: list[str], env: dict[str, str], cwd: Path) -> None:
        self.lines: list[str] = []
        self.process = subprocess.Popen(
            [*BELVEDERE, "run", "--headless", *argv],
            cwd=cwd,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,  # its script is its child: both end together
        )
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            self.lines.append(line.rstrip("\n"))

    def wait_for(self, text: str) -> None:
        wait_until(
            lambda: any(text in line for line in self.lines),
            what=f"{text!r} in the script's output",
            detail=lambda: self.lines[-5:],
        )

    def stop(self) -> None:
        if self.process.poll() is None:
            os.killpg(self.process.pid, signal.SIGINT)
        self.process.wait(timeout=DEADLINE)


@pytest.fixture
def elsewhere(tmp_path: Path) -> Path:
    """A directory with no package and no workspace around it."""
    path = tmp_path / "elsewhere"
    path.mkdir()
    return path


@pytest.fixture
def person_publisher(endpoint: str, tmp_path: Path) -> Iterator[Script]:
    """learning_topic's person_publisher.py, run as after sourcing the workspace."""
    env = {**_bare_env(), "ROS_PACKAGE_PATH": str(EXAMPLES)}
    script = Script(["learning_topic", "person_publisher.py"], env, tmp_path)
    try:
        script.wait_for("Publish Person Info")
        yield script
    finally:
        script.stop()


def _bare(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*BELVEDERE, *args],
        cwd=cwd,
        env=_bare_env(),
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )


def test_a_bare_terminal_echoes_and_records_a_learners_type(
    person_publisher: Script, elsewhere: Path
) -> None:
    echo = _bare(["topic", "echo", "-n", "1", "/person_info"], elsewhere)
    assert echo.returncode == 0, echo.stderr
    assert 'name: "Tom"\nage: 18\nsex: 1\n---' in echo.stdout
    record = _bare(["bag", "record", "-O", "people", "-l", "3", "/person_info"], elsewhere)
    assert record.returncode == 0, record.stderr
    assert "warning" not in record.stderr, record.stderr
    bag = open_bag(elsewhere / "people.bag")
    try:
        (conn,) = bag.connections
        # the text as the package's file has it: what ROS 1's rosbag would have recorded
        assert conn.md5sum == "b3f7ec37d11629ec3010e27635cf22a9"
        assert conn.definition == (EXAMPLES / "learning_topic/msg/Person.msg").read_text()
        assert bag.counts == {conn.id: 3}
    finally:
        bag.close()


def test_a_bare_terminal_calls_a_learners_service(
    endpoint: str, tmp_path: Path, elsewhere: Path
) -> None:
    server = Script(
        [str(EXAMPLES / "learning_service" / "scripts" / "person_server.py")],
        _bare_env(),
        tmp_path,
    )
    try:
        server.wait_for("Ready to show person information.")
        call = _bare(["service", "call", "/show_person", "{name: Ann, age: 3, sex: 2}"], elsewhere)
        assert call.returncode == 0, call.stderr
        assert 'result: "OK"' in call.stdout
        server.wait_for("Person: name:Ann  age:3  sex:2")
    finally:
        server.stop()


# --- answers that lie ------------------------------------------------------------------------


class Liar:
    """Another process's queryable for types, answering ``answer`` (bytes) about any."""

    def __init__(self, endpoint: str, answer: bytes) -> None:
        self.session, _ = open_session(endpoint)
        self.queryable = self.session.declare_queryable(
            f"bv/{TEST_DOMAIN}/y/**", lambda q: q.reply(q.key_expr, answer)
        )

    def close(self) -> None:
        self.queryable.undeclare()  # type: ignore[no-untyped-call]
        self.session.close()  # type: ignore[no-untyped-call]


def _answer(name: str, text: str, md5: str) -> bytes:
    return json.dumps({"type": name, "definition": text, "md5sum": md5}).encode()


@pytest.mark.parametrize(
    ("name", "answer", "expected"),
    [
        (
            "liar_a/msg/T",
            _answer("liar_a/msg/T", "int32 x\n", "0" * 32),
            "the definition of liar_a/T does not match its MD5 sum",
        ),
        (
            "liar_b/msg/T",
            _answer("liar_b/msg/T", "int32 x y z\n", "0" * 32),
            "malformed declaration 'int32 x y z'",
        ),
        ("liar_c/msg/T", b"{not json", "not a type's definition as belvedere answers one"),
        (
            "liar_d/msg/T",
            _answer("liar_d/msg/T", "int32 " + "x" * 2_200_000, "0" * 32),
            "past the 2101248 an answer may hold",
        ),
    ],
)
def test_an_answer_that_does_not_check_out_is_an_error_saying_why(
    endpoint: str, name: str, answer: bytes, expected: str
) -> None:
    liar = Liar(endpoint, answer)
    transport = ZenohTransport(endpoint=endpoint)
    try:
        with pytest.raises(BelvedereError) as caught:
            types().resolve(name)
        assert expected in caught.value.describe()
        assert f"the graph's answer about {name}" in caught.value.describe()
        assert name not in types().store.fielddefs
        # asked again later, not at every message
        with pytest.raises(MessageTypeError):
            types().resolve(name)
    finally:
        transport.close()
        liar.close()


def test_a_type_nobody_knows_is_unknown_once_asked(endpoint: str) -> None:
    transport = ZenohTransport(endpoint=endpoint)
    try:
        with pytest.raises(MessageTypeError, match="unknown message type 'nobody_msgs/T'"):
            types().resolve("nobody_msgs/T")
    finally:
        transport.close()


def test_a_process_answers_for_the_types_it_knows(endpoint: str) -> None:
    transport = ZenohTransport(endpoint=endpoint)
    session: Any = None
    try:
        session, _ = open_session(endpoint)
        key = f"bv/{TEST_DOMAIN}/y/std_msgs%msg%Header"
        replies = list(session.get(key, timeout=DEADLINE, target=zenoh.QueryTarget.ALL))
        (answer,) = [json.loads(r.ok.payload.to_bytes()) for r in replies if r.ok is not None]
        assert answer["md5sum"] == "2176decaecbce78abc3b96ef049fabed"
        assert answer["definition"].startswith("uint32 seq\ntime stamp\nstring frame_id\n")
    finally:
        if session is not None:
            session.close()
        transport.close()
