"""Types learnt from a bag's own definitions, as ``rosbag play`` plays a bag whose package is
not on this machine: a learner's learning_topic/Person recorded in a process that has the
package, then read, played and echoed by processes that do not (no package path, run from
outside any workspace); and definitions that lie (an MD5 sum of another text, malformed,
huge, a type known here otherwise)."""

from __future__ import annotations

import hashlib
import logging
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from belvedere.bags import Connection, Decoder
from belvedere.msgs import types
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE

PERSON = (EXAMPLES / "learning_topic" / "msg" / "Person.msg").read_text()
# genmsg's MD5 text: constants as written right of '=', then the fields
PERSON_MD5 = hashlib.md5(
    b"uint8 unknown=0\nuint8 male=1\nuint8 female=2\nstring name\nuint8 age\nuint8 sex"
).hexdigest()


def _bare_env() -> dict[str, str]:
    """A terminal with nothing sourced: no package path at all."""
    drop = ("ROS_PACKAGE_PATH", "BELVEDERE_PACKAGE_PATH")
    return {k: v for k, v in os.environ.items() if k not in drop}


def _run(args: list[str], cwd: Path, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "belvedere", *args],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )


def _record_person_bag(path: Path) -> None:
    """Three Person messages recorded by belvedere's recorder in a process that has the
    package (a graph of its own, its recording's own subscription)."""
    script = f"""
from pathlib import Path
from belvedere.bags import GraphRecording, Recorder, parse_record_args
from belvedere.graph import Graph
g = Graph(sim_time=True)
pub = g.create_node("person_publisher").publisher("/person_info", "learning_topic/Person")
count = iter(range(3))
g.create_node("tick").timer(0.1, lambda: pub.publish_data(
    {{"name": "Tom", "age": 18 + next(count, 0), "sex": 1}}))
recorder = Recorder(parse_record_args(["-l", "3", "-O", {str(path)!r}, "/person_info"]))
recorder.start(GraphRecording(g.create_node("record"), recorder))
g.run(rtf=None, until=recorder.finished.is_set)
recorder.stop()
"""
    env = {**_bare_env(), "ROS_PACKAGE_PATH": str(EXAMPLES)}
    done = subprocess.run(
        [sys.executable, "-c", script],
        env=env,
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert path.is_file()


def test_a_bag_of_a_type_not_on_this_machine_is_read_played_and_echoed(
    tmp_path: Path, endpoint: str
) -> None:
    bag = tmp_path / "person.bag"
    _record_person_bag(bag)
    elsewhere = tmp_path / "elsewhere"  # no package, no workspace around it
    elsewhere.mkdir()
    env = _bare_env()
    info = _run(["bag", "info", str(bag)], elsewhere, env)
    assert info.returncode == 0, info.stderr
    assert f"learning_topic/Person [{PERSON_MD5}]" in info.stdout
    play = _run(["bag", "play", "--immediate", str(bag)], elsewhere, env)
    assert play.returncode == 0, play.stderr
    assert "warning" not in play.stderr, play.stderr
    # another bare terminal echoes the playing: it learns the type from the player
    echo = subprocess.Popen(
        [sys.executable, "-m", "belvedere", "topic", "echo", "-n", "1", "/person_info"],
        cwd=elsewhere,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    player = subprocess.Popen(
        [sys.executable, "-m", "belvedere", "bag", "play", "-q", "-l", str(bag)],
        cwd=elsewhere,
        env=env,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        out, err = echo.communicate(timeout=DEADLINE)
    finally:
        echo.kill()
        player.send_signal(signal.SIGINT)
        _, said = player.communicate(timeout=DEADLINE)
    assert echo.returncode == 0, err
    assert 'name: "Tom"\nage: ' in out
    assert "sex: 1\n---" in out
    assert "warning" not in said, said


# --- definitions that lie -------------------------------------------------------------------


def _conn(msgtype: str, definition: str, md5: str, topic: str = "/x") -> Connection:
    return Connection(7, topic, msgtype, "ros1", md5, definition)


def _warnings(caplog: pytest.LogCaptureFixture) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]


def test_a_definition_is_read_by_genmsg_rules_and_its_md5_checked(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """'uint8 male = 1' is a constant (rosbags' parser took it for a field: three bytes
    more per message, every message read wrong)."""
    msgtype = "bagonly_a/msg/Person"
    assert Decoder().usable(_conn(msgtype, PERSON, PERSON_MD5), "p.bag")
    constants, fields = types().store.fielddefs[msgtype]
    assert [c[0] for c in constants] == ["unknown", "male", "female"]
    assert [f[0] for f in fields] == ["name", "age", "sex"]
    assert types().definitions[msgtype].text == PERSON  # what bags and the graph pass on
    assert _warnings(caplog) == []


def test_a_definition_of_another_md5_sum_is_skipped_naming_bag_connection_and_topic(
    caplog: pytest.LogCaptureFixture,
) -> None:
    msgtype = "bagonly_b/msg/Person"
    assert not Decoder().usable(_conn(msgtype, PERSON, "0" * 32, "/person_info"), "p.bag")
    assert _warnings(caplog) == [
        "p.bag: skipping /person_info (connection 7): its definition of bagonly_b/Person does "
        f"not match the connection's MD5 sum ({'0' * 32} given, {PERSON_MD5} computed from "
        "the definition)"
    ]
    assert msgtype not in types().store.fielddefs  # nothing learnt from it


def test_a_malformed_section_is_one_warning_at_its_line(caplog: pytest.LogCaptureFixture) -> None:
    text = "bagonly_c/Inner inner\n" + "=" * 80 + "\nMSG bagonly_c/Inner\nint32 x\n"
    assert not Decoder().usable(_conn("bagonly_c/msg/Outer", text, "*"), "p.bag")
    (warning,) = _warnings(caplog)
    assert warning == (
        "p.bag: skipping /x (connection 7): cannot read its type bagonly_c/msg/Outer: its "
        "definition does not parse (line 3: expected 'MSG: pkg/Type' after a line of '=', "
        "not 'MSG bagonly_c/Inner')"
    )


def test_a_huge_definition_is_refused_unread(caplog: pytest.LogCaptureFixture) -> None:
    decoder = Decoder()
    line = "int32 " + "x" * 2_000_000 + "\n"  # one line past the cap: never parsed
    assert not decoder.usable(_conn("bagonly_d/msg/Big", line, "*"), "p.bag")
    (warning,) = _warnings(caplog)
    assert warning.startswith("p.bag: skipping /x: its type's definition (1.9 MiB)")
    sections = "".join(f"{'=' * 80}\nMSG: bagonly_e/T{i}\nint8 a\n" for i in range(300))
    assert not Decoder().usable(_conn("bagonly_e/msg/Top", "int8 a\n" + sections, "*"), "p.bag")
    assert _warnings(caplog)[-1] == (
        "p.bag: skipping /x (connection 7): cannot read its type bagonly_e/msg/Top: the "
        "definition has more than 256 types"
    )


def test_a_type_known_here_otherwise_is_said_and_converted(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A std_msgs/String whose text says int32: another layout, never read as a string."""
    text = "int32 data\n"
    md5 = hashlib.md5(b"int32 data").hexdigest()
    assert Decoder().usable(_conn("std_msgs/msg/String", text, md5), "p.bag")
    (warning,) = _warnings(caplog)
    assert warning.startswith(
        "p.bag: /x: the bag's std_msgs/String differs from belvedere's (std_msgs/String here "
        "is not the one it was written with (MD5 sum 992ce8a1687cec8c8bd883ec73ca41d1 here, "
    )
