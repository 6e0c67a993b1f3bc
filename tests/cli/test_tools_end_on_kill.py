"""``belvedere node kill`` of a tool's node ends the tool, as ``rosnode kill`` ends rostopic
(Debian's rostopic prints ``shutdown request: user request`` and exits 0), and of one node of
a launch ends that node alone, as roslaunch reports a process that finished."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from belvedere.cli import main
from belvedere.graph import Graph, ZenohTransport
from belvedere.tf import static_transform_publisher
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]


@pytest.fixture
def graph(endpoint: str) -> Iterator[Graph]:
    """A graph in this process: /chatter ten times a second, and one static transform."""
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint), clock_hz=None)
    node = graph.create_node("talker")
    chatter = node.publisher("/chatter", "std_msgs/String")
    node.timer(0.1, lambda: chatter.publish_data({"data": "tick"}))
    static_transform_publisher(node, ["0", "0", "1", "0", "0", "0", "map", "odom"])
    graph.start(rtf=None)
    yield graph
    graph.shutdown()


def _nodes(graph: Graph) -> set[str]:
    transport = graph.transport
    assert isinstance(transport, ZenohTransport)
    return transport.info(timeout=0.5).nodes


TOOLS = {
    "topic pub": ["topic", "pub", "-r", "5", "/said", "std_msgs/String", "data: hi"],
    "topic echo": ["topic", "echo", "/chatter"],
    "topic hz": ["topic", "hz", "/chatter"],
    "topic bw": ["topic", "bw", "/chatter"],
    "tf echo": ["tf", "echo", "map", "odom"],
}


@pytest.mark.parametrize("tool", TOOLS)
def test_a_tool_ends_when_its_node_is_killed(tool: str, graph: Graph) -> None:
    proc = subprocess.Popen(
        [*BELVEDERE, "-q", *TOOLS[tool]], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        name = f"/belvedere_{tool.split()[0]}_{proc.pid}"
        wait_until(lambda: name in _nodes(graph), what=f"{name} on the graph")
        assert main(["-q", "node", "kill", name]) == 0
        out, err = proc.communicate(timeout=DEADLINE)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
    assert out.endswith("shutdown request: user request\n")
    assert "Traceback" not in err, err


def test_a_killed_node_of_a_launch_ends_alone(graph: Graph, tmp_path: Path) -> None:
    """roslaunch's way: the killed node's process "finished cleanly", the others run on."""
    launch = tmp_path / "two.launch"
    launch.write_text(
        "<launch>\n"
        '  <node pkg="tf2_ros" type="static_transform_publisher" name="a"'
        ' args="0 0 1 0 0 0 odom base"/>\n'
        '  <node pkg="tf2_ros" type="static_transform_publisher" name="b"'
        ' args="0 0 1 0 0 0 base laser"/>\n'
        "</launch>\n"
    )
    log = tmp_path / "launch.err"
    with open(log, "w") as err:
        proc = subprocess.Popen([*BELVEDERE, "launch", "--headless", str(launch)], stderr=err)
    try:
        wait_until(lambda: {"/a", "/b"} <= _nodes(graph), what="the launch's nodes")
        assert main(["-q", "node", "kill", "/a"]) == 0
        wait_until(
            lambda: "[a-1] process has finished cleanly\n" in log.read_text(),
            what="roslaunch's line for /a",
            detail=log.read_text,
        )
        assert "/b" in _nodes(graph)
        assert proc.poll() is None  # beside a running graph: until its last node has ended
        assert main(["-q", "node", "kill", "/b"]) == 0
        assert proc.wait(timeout=DEADLINE) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert "all processes on machine have died, roslaunch will exit" in log.read_text()


def test_a_run_of_a_built_in_node_ends_with_its_node(graph: Graph) -> None:
    proc = subprocess.Popen(
        [*BELVEDERE, "run", "-q", "tf2_ros", "static_transform_publisher",
         "0", "0", "1", "0", "0", "0", "odom", "base", "__name:=stp"],
        stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        wait_until(lambda: "/stp" in _nodes(graph), what="/stp on the graph")
        assert main(["-q", "node", "kill", "/stp"]) == 0
        _, err = proc.communicate(timeout=DEADLINE)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
