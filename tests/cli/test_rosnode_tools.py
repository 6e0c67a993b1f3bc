"""``belvedere node ping|kill|machine|cleanup``, ``topic find``, ``service
info|find|args|uri`` and ``wtf`` on a graph of their own, with learners' rospy scripts run by
``belvedere run`` in processes of their own."""

from __future__ import annotations

import os
import re
import signal
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from belvedere.cli import main
from belvedere.graph import Graph, ZenohTransport
from tests.ros1.rospy_oracle import SCRIPTS
from tests.waiting import DEADLINE, wait_until


def _tool(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    capsys.readouterr()
    code = main(["-q", *argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def scripts(endpoint: str, tmp_path: Path) -> Iterator[dict[str, subprocess.Popen[str]]]:
    script = SCRIPTS / "killable.py"
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    run = [sys.executable, "-m", "belvedere", "run", "-q", "--headless", str(script)]
    procs: dict[str, subprocess.Popen[str]] = {}
    try:
        for role in ("listener", "talker"):
            proc = subprocess.Popen(
                [*run, role, str(tmp_path / f"{role}.done")],
                env=env,
                stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL,
                text=True,
                start_new_session=True,  # its script's process too is ended below
            )
            procs[role] = proc
            assert proc.stdout is not None
            assert proc.stdout.readline().strip() == "ready"
        yield procs
    finally:
        for proc in procs.values():
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def test_the_graph_as_rosnode_rostopic_and_rosservice_see_it(
    scripts: dict[str, subprocess.Popen[str]], capsys: pytest.CaptureFixture[str]
) -> None:
    wait_until(
        lambda: _tool(capsys, "node", "list")[1] == "/listener\n/talker\n", what="both nodes"
    )
    assert _tool(capsys, "topic", "find", "std_msgs/String")[1] == "/chatter\n/status\n"
    assert _tool(capsys, "topic", "find", "geometry_msgs/Twist") == (0, "\n", "")
    code, _, err = _tool(capsys, "topic", "find", "std_msgs/Strin")
    assert code == 1
    assert "unknown message type 'std_msgs/Strin'" in err
    assert "did you mean std_msgs/String" in err
    info = _tool(capsys, "service", "info", "/enable")[1]
    assert info == ("Node: /listener\nURI: bv/231/s/enable\nType: std_srvs/SetBool\nArgs: data\n")
    assert _tool(capsys, "service", "args", "enable")[1] == "data\n"
    assert _tool(capsys, "service", "uri", "/enable")[1] == "bv/231/s/enable\n"
    assert _tool(capsys, "service", "find", "std_srvs/SetBool")[1] == "/enable\n"
    assert _tool(capsys, "service", "find", "std_srvs/Trigger")[1] == "\n"
    code, _, err = _tool(capsys, "service", "info", "/enabel")
    assert (code, err) == (
        1,
        "error: service /enabel is not offered by any node\n  hint: did you mean /enable?\n",
    )
    host = socket.gethostname()
    assert _tool(capsys, "node", "machine")[1] == f"{host}\n"
    assert _tool(capsys, "node", "machine", host)[1] == "/listener\n/talker\n"
    code, _, err = _tool(capsys, "node", "machine", "elsewhere")
    assert code == 1
    assert f"no node runs on machine 'elsewhere'\n  hint: machines: {host}" in err


def test_ping_kill_and_cleanup(
    scripts: dict[str, subprocess.Popen[str]],
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
) -> None:
    wait_until(
        lambda: _tool(capsys, "node", "list")[1] == "/listener\n/talker\n", what="both nodes"
    )
    code, out, _ = _tool(capsys, "node", "ping", "-c", "2", "/listener")
    lines = out.splitlines()
    assert code == 0
    assert lines[:2] == ["node is [/listener]", "pinging /listener with a timeout of 3.0s"]
    # the process that holds the node answers: the one node info names
    process = _tool(capsys, "node", "info", "/listener")[1].split("Process: ")[1].split("\n")[0]
    assert process.endswith(f" on {socket.gethostname()}")
    for line in lines[2:]:
        assert re.fullmatch(rf"reply from {process}\ttime=\d+\.\d+ms", line), line
    assert len(lines) == 4
    code, _, err = _tool(capsys, "node", "ping", "-c", "1", "/listner")
    assert (code, err) == (1, "error: unknown node /listner\n  hint: did you mean /listener?\n")
    assert _tool(capsys, "node", "cleanup") == (0, "", "")
    # a process that stops answering (SIGSTOP) is what cleanup names
    os.kill(scripts["talker"].pid, 19)
    try:
        code, out, _ = _tool(capsys, "node", "cleanup")
        assert code == 1
        assert out.startswith("Unable to contact the following nodes:\n * /talker\n")
    finally:
        os.kill(scripts["talker"].pid, 18)
    # kill: the script's shutdown hook runs, rospy.spin returns, its process ends (the
    # talker first: the listener's process, started first, is where the graph meets)
    assert _tool(capsys, "node", "kill", "/talker") == (0, "killing /talker\nkilled\n", "")
    talker = scripts["talker"]
    out, _ = talker.communicate(timeout=DEADLINE)
    assert talker.returncode == 0
    assert out == "shutdown request: user request\nspin returned\n"
    assert (tmp_path / "talker.done").read_text() == "hook ran"
    assert _tool(capsys, "node", "list")[1] == "/listener\n"
    assert _tool(capsys, "node", "kill", "-a") == (0, "killing /listener\nkilled\n", "")
    scripts["listener"].wait(timeout=DEADLINE)
    assert (tmp_path / "listener.done").read_text() == "hook ran"
    code, _, err = _tool(capsys, "node", "kill", "/talker")
    assert (code, err) == (1, "error: unknown node /talker\n  hint: see 'belvedere node list'\n")


def test_wtf_names_what_a_learner_gets_wrong(
    endpoint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint), clock_hz=None)
    try:
        graph.params.set("/use_sim_time", True)
        node = graph.create_node("robot")
        node.subscribe("/cmd_vel", "geometry_msgs/Twist", lambda m: None)
        node.publisher("/odom", "nav_msgs/Odometry")
        static = node.publisher("/tf_static", "tf2_msgs/TFMessage", latch=True)

        def link(parent: str, child: str) -> dict[str, object]:
            return {"header": {"frame_id": parent}, "child_frame_id": child}

        edges = [("odom", "base_link"), ("map", "base_link"), ("a", "b"), ("b", "a")]
        static.publish_data({"transforms": [link(p, c) for p, c in edges]})
        graph.start(rtf=None)
        code, out, _ = _tool(capsys, "wtf", "--listen", "0.5")
    finally:
        graph.shutdown()
    assert code == 1
    assert out == (
        "Found 2 warning(s).\n"
        "Warnings are things that may be just fine, but are sometimes at fault\n\n"
        "WARNING The following node subscriptions are unconnected:\n"
        " * /robot:\n   * /cmd_vel\n\n"
        "WARNING The following node publications have no subscribers:\n"
        " * /robot:\n   * /odom\n\n\n"
        "Found 4 error(s).\n\n"
        "ERROR /use_sim_time is set but no publisher of /clock is present\n"
        "ERROR The following TF frames have more than one parent (a frame has one):\n"
        " * base_link: map, odom\n\n"
        "ERROR The TF frames form a loop (each frame's parents lead back to it):\n"
        " * a -> b -> a\n\n"
        "ERROR The TF frames form more than one tree (no transform between the trees):\n"
        " * map: base_link, map\n * odom: odom\n\n"
    )


def test_wtf_on_a_sound_graph(endpoint: str, capsys: pytest.CaptureFixture[str]) -> None:
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint), clock_hz=None)
    try:
        node = graph.create_node("robot")
        node.subscribe("/cmd_vel", "geometry_msgs/Twist", lambda m: None)
        node.publisher("/cmd_vel", "geometry_msgs/Twist")
        graph.start(rtf=None)
        assert _tool(capsys, "wtf", "--listen", "0.2") == (0, "No errors or warnings\n", "")
    finally:
        graph.shutdown()
