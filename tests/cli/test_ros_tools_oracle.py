"""``belvedere topic``/``service``/``node``/``wtf`` against Debian's ``rostopic``,
``rosservice``, ``rosnode`` and ``roswtf``: one graph layout, made by the same rospy script
under a real roscore and under ``belvedere run``, and the tools' output compared line for
line.

Skipped where Debian's ROS 1 (roscore, rospy, rostopic, rosservice) is absent."""

from __future__ import annotations

import os
import re
import signal
import socket
import subprocess
import sys
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path

import pytest

from belvedere.cli import main
from tests.debian_ros import ROS_PYTHON
from tests.ros1.rospy_oracle import REPO, SCRIPTS, Master, master, missing_oracle
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


KILLABLE = SCRIPTS / "killable.py"
"""Two nodes (the listener's subscription unconnected); ``rosnode kill`` ends the talker."""

GRAPH_LINES: tuple[tuple[str, ...], ...] = (
    ("topic", "find", "std_msgs/String"),
    ("topic", "find", "geometry_msgs/Twist"),
    ("service", "info", "/enable"),
    ("service", "args", "/enable"),
    ("service", "find", "std_srvs/SetBool"),
    ("node", "machine"),
    ("node", "machine", socket.gethostname()),
)
ROS_TOOLS = {"topic": ROSTOPIC, "service": ROSSERVICE, "node": Path("/usr/bin/rosnode")}


def _comparable(line: tuple[str, ...], text: str) -> str:
    """What both graphs say alike: not the URI of a service (rosservice's is an address,
    belvedere's a Zenoh key) nor roscore's own /rosout node."""
    kept = [row for row in text.split("\n") if not row.startswith("URI: ") and row != "/rosout"]
    return "\n".join(kept)


def _unconnected_block(text: str) -> str:
    """roswtf's warning about unconnected subscriptions, down to the blank line after it,
    without roscore's own /rosout node (the scripts do not log to /rosout)."""
    start = text.index("WARNING The following node subscriptions are unconnected:")
    block = text[start : text.index("\n\n", start) + 2]
    return block.replace(" * /rosout:\n   * /rosout\n", "")


def _graph_tools(
    run_tool: Callable[[tuple[str, ...]], str],
    procs: dict[str, subprocess.Popen[str]],
    wtf: str,
) -> dict[str, str]:
    found = {" ".join(line): _comparable(line, run_tool(line)) for line in GRAPH_LINES}
    found["wtf"] = _unconnected_block(wtf)
    found["kill"] = run_tool(("node", "kill", "/talker"))
    talker = procs["talker"]
    out, _ = talker.communicate(timeout=DEADLINE)
    found["talker's output"] = out
    found["talker's exit"] = str(talker.returncode)
    return found


def _interrupt(procs: Iterable[subprocess.Popen[str]]) -> None:
    """Ctrl-C to each script still running, as a terminal sends it: to its process group
    (``belvedere run`` and the script's process under it); rospy shuts down on it."""
    for proc in procs:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(timeout=DEADLINE)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _killable(
    argv: Sequence[str], env: dict[str, str], role: str, folder: Path
) -> subprocess.Popen[str]:
    """killable.py in a process group of its own, once it has said it is ready."""
    proc = subprocess.Popen(
        [*argv, role, str(folder / f"{role}.done")],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        start_new_session=True,
    )
    assert proc.stdout is not None
    assert proc.stdout.readline().strip() == "ready", f"{argv} did not start"
    return proc


@pytest.fixture
def fresh_roscore(roscore: Master) -> Iterator[Master]:
    """A roscore of its own (a master remembers the types of topics whose nodes are gone:
    rostopic find would list the other test's)."""
    with master() as core:
        yield core


def test_rosnode_kill_machine_rostopic_find_rosservice_info_and_roswtf(
    fresh_roscore: Master, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    roscore = fresh_roscore
    script = KILLABLE
    roswtf = Path("/usr/bin/roswtf")
    if not roswtf.is_file():
        pytest.skip("roswtf is not installed")
    ros_dir, bv_dir = tmp_path / "ros", tmp_path / "belvedere"
    ros_dir.mkdir()
    bv_dir.mkdir()
    # under ROS
    ros = [str(ROS_PYTHON), str(script)]
    procs = {role: _killable(ros, roscore.env, role, ros_dir) for role in ("listener", "talker")}
    try:

        def ros_tool(line: tuple[str, ...]) -> str:
            argv = [str(ROS_TOOLS[line[0]]), *line[1:]]
            return subprocess.run(
                argv, env=roscore.env, capture_output=True, text=True, check=True
            ).stdout

        wtf = subprocess.run(
            [str(roswtf)], env=roscore.env, capture_output=True, text=True, check=False
        ).stdout
        expected = _graph_tools(ros_tool, procs, re.sub(r"\x1b\[[0-9;]*m", "", wtf))
    finally:
        _interrupt(procs.values())
    # under belvedere
    env = {**os.environ, "PYTHONPATH": str(REPO / "src"), "PYTHONUNBUFFERED": "1"}
    run = [sys.executable, "-m", "belvedere", "run", "-q", "--headless", str(script)]
    procs = {role: _killable(run, env, role, bv_dir) for role in ("listener", "talker")}
    try:

        def ours(line: tuple[str, ...]) -> str:
            capsys.readouterr()
            assert main(["-q", *line]) == 0, line
            return capsys.readouterr().out

        wait_until(lambda: ours(("node", "list")) == "/listener\n/talker\n", what="both nodes")
        capsys.readouterr()
        main(["-q", "wtf"])
        got = _graph_tools(ours, procs, capsys.readouterr().out)
    finally:
        _interrupt(procs.values())
    assert got == expected
    for folder in (ros_dir, bv_dir):
        assert (folder / "talker.done").read_text() == "hook ran"
    # what the comparison establishes, spelt out
    assert (
        expected["service info /enable"] == "Node: /listener\nType: std_srvs/SetBool\nArgs: data\n"
    )
    assert expected["kill"] == "killing /talker\nkilled\n"
    assert expected["talker's output"] == "shutdown request: user request\nspin returned\n"
    assert expected["wtf"] == (
        "WARNING The following node subscriptions are unconnected:\n * /listener:\n"
        "   * /chatter\n\n"
    )
