"""``belvedere topic``/``service`` against Debian's ``rostopic``/``rosservice``: one graph
layout, made by the same rospy script under a real roscore and under ``belvedere run``, and
the tools' output compared line for line.

Skipped where Debian's ROS 1 (roscore, rospy, rostopic, rosservice) is absent."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path

import pytest

from belvedere.cli import main
from tests.debian_ros import ROS_PYTHON
from tests.ros1.rospy_oracle import REPO, Master, master, missing_oracle
from tests.waiting import DEADLINE, wait_until

pytestmark = pytest.mark.oracle

ROSTOPIC = Path("/usr/bin/rostopic")
ROSSERVICE = Path("/usr/bin/rosservice")

LAYOUT = """
import os, sys, time
import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from std_srvs.srv import Empty, EmptyResponse, Trigger, TriggerResponse

role, stop = sys.argv[1], sys.argv[2]
rospy.init_node(role, disable_rosout=True)
held = []
if role == "talker":
    held.append(rospy.Publisher("/chatter", String, queue_size=1))
    held.append(rospy.Publisher("/cmd_vel", Twist, queue_size=1))
elif role == "listener":
    held.append(rospy.Subscriber("/chatter", String, lambda m: None))
    held.append(rospy.Subscriber("/joint_states", JointState, lambda m: None))
else:
    held.append(rospy.Publisher("/chatter", String, queue_size=1))
    held.append(rospy.Publisher("/robot/status", String, queue_size=1))
    held.append(rospy.Subscriber("/joint_states", JointState, lambda m: None))
    held.append(rospy.Subscriber("/robot/cmd", Twist, lambda m: None))
    held.append(rospy.Service("/reset", Empty, lambda req: EmptyResponse()))
    held.append(rospy.Service("/trigger", Trigger, lambda req: TriggerResponse(True, "done")))
print("ready", flush=True)
while not os.path.exists(stop):
    time.sleep(0.05)
"""
ROLES = ("talker", "listener", "other")
TOPICS = ("/chatter", "/cmd_vel", "/joint_states", "/robot/cmd", "/robot/status")

TOPIC_LINES: tuple[tuple[str, ...], ...] = (
    ("list", "-v"),
    ("list", "-v", "-p"),
    ("list", "-v", "-s"),
    ("list",),
    ("list", "-p"),
    ("list", "-s"),
    ("list", "-v", "/robot"),
    ("list", "/robot"),
)
SERVICE_LINES: tuple[tuple[str, ...], ...] = (("call", "/reset"), ("call", "/trigger"))


@pytest.fixture(scope="module")
def roscore() -> Iterator[Master]:
    reason = missing_oracle()
    if reason is None and not (ROSTOPIC.is_file() and ROSSERVICE.is_file()):
        reason = "rostopic or rosservice is not installed"
    if reason is not None:
        pytest.skip(reason)
    with master() as core:
        yield core


def _start(argv: Sequence[str], env: dict[str, str]) -> subprocess.Popen[str]:
    """A layout process, once it has said it is ready."""
    proc = subprocess.Popen(
        list(argv), env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True
    )
    assert proc.stdout is not None
    assert proc.stdout.readline().strip() == "ready", f"{argv} did not start"
    return proc


def _stop(procs: list[subprocess.Popen[str]], stop: Path) -> None:
    stop.touch()
    for proc in procs:
        try:
            proc.wait(timeout=DEADLINE)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def _as_listed(text: str) -> str:
    """rostopic's listing without roscore's own topics, its rows in name order (it lists
    them in the master's order of registration)."""
    out: list[str] = []
    rows: list[str] = []
    for line in text.split("\n"):
        if "/rosout" in line:
            continue
        if line.startswith(" * "):
            rows.append(line)
            continue
        out += [*sorted(rows), line]
        rows = []
    return "\n".join([*out, *sorted(rows)])


def _ros_outputs(core: Master, script: Path, stop: Path) -> dict[tuple[str, ...], str]:
    procs = [_start([str(ROS_PYTHON), str(script), role, str(stop)], core.env) for role in ROLES]
    try:
        found = {}
        for line in TOPIC_LINES:
            done = subprocess.run(
                [str(ROSTOPIC), *line], env=core.env, capture_output=True, text=True, check=True
            )
            found[("topic", *line)] = _as_listed(done.stdout)
        for line in SERVICE_LINES:
            done = subprocess.run(
                [str(ROSSERVICE), *line], env=core.env, capture_output=True, text=True, check=True
            )
            found[("service", *line)] = done.stdout
        return found
    finally:
        _stop(procs, stop)


def _belvedere_outputs(
    script: Path, stop: Path, capsys: pytest.CaptureFixture[str]
) -> dict[tuple[str, ...], str]:
    env = {**os.environ, "PYTHONPATH": str(REPO / "src"), "PYTHONUNBUFFERED": "1"}
    run = [sys.executable, "-m", "belvedere", "run", "-q", "--headless"]
    # the first provides the graph (it is ready once it listens); the others join it
    procs = [_start([*run, str(script), role, str(stop)], env) for role in ROLES]
    try:

        def listed() -> bool:
            capsys.readouterr()
            main(["topic", "list"])
            return capsys.readouterr().out.split() == list(TOPICS)

        wait_until(listed, what="every topic of the layout")
        found = {}
        for verb, lines in (("topic", TOPIC_LINES), ("service", SERVICE_LINES)):
            for line in lines:
                capsys.readouterr()
                assert main([verb, *line]) == 0
                found[(verb, *line)] = capsys.readouterr().out
        return found
    finally:
        _stop(procs, stop)


def test_the_listings_and_calls_of_rostopic_and_rosservice(
    roscore: Master, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = tmp_path / "layout.py"
    script.write_text(LAYOUT)
    expected = _ros_outputs(roscore, script, tmp_path / "stop_ros")
    got = _belvedere_outputs(script, tmp_path / "stop_belvedere", capsys)
    for line, text in expected.items():
        assert got[line] == text, line
    assert sum(text.count("\n") for text in expected.values()) == 46
    # what the comparison establishes, spelt out
    assert expected[("topic", "list", "-v")] == (
        "\nPublished topics:\n"
        " * /chatter [std_msgs/String] 2 publishers\n"
        " * /cmd_vel [geometry_msgs/Twist] 1 publisher\n"
        " * /robot/status [std_msgs/String] 1 publisher\n"
        "\nSubscribed topics:\n"
        " * /chatter [std_msgs/String] 1 subscriber\n"
        " * /joint_states [sensor_msgs/JointState] 2 subscribers\n"
        " * /robot/cmd [geometry_msgs/Twist] 1 subscriber\n\n"
    )
    assert expected[("service", "call", "/reset")] == "\n"  # an empty response: nothing
