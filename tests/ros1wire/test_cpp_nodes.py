"""The course's C++ nodes, built with Debian's catkin and g++, against belvedere's master:
every message crosses both ways, a message type only the C++ package defines is learnt from
the wire, and a C++ service is called from the graph."""

from __future__ import annotations

import os
import subprocess
import sys
from functools import partial
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.ros1wire import MasterHandle
from tests.ros1wire.catkin import PACKAGE, build_workspace, missing_catkin
from tests.ros1wire.conftest import Ros1
from tests.waiting import DEADLINE, wait_until

pytestmark = pytest.mark.usefixtures("needs_debian_ros")


@pytest.fixture(scope="session")
def workspace() -> Path:
    why = missing_catkin()
    if why:
        pytest.skip(why)
    return build_workspace()


def _node(workspace: Path, name: str) -> str:
    return str(workspace / "devel" / "lib" / PACKAGE / name)


@pytest.fixture
def ros(ros_graph: tuple[Graph, MasterHandle]) -> Ros1:
    return Ros1(ros_graph[1].uri)


def _finish(proc: subprocess.Popen[str]) -> tuple[str, str]:
    try:
        return proc.communicate(timeout=DEADLINE)
    finally:
        proc.kill()


def test_a_cpp_talker_reaches_a_graph_subscriber(
    workspace: Path, ros_graph: tuple[Graph, MasterHandle], ros: Ros1
) -> None:
    graph, _ = ros_graph
    heard: list[str] = []
    node = graph.create_node("listener")
    node.subscribe("/chatter", "std_msgs/String", lambda m: heard.append(m.data))
    talker = ros.start(_node(workspace, "talker"), "_count:=40")
    _finish(talker)
    wait_until(lambda: len(heard) >= 40, what="40 messages", detail=lambda: heard[-3:])
    assert heard == [f"hello world {i}" for i in range(40)]


def test_a_graph_publisher_reaches_the_cpp_listener(
    workspace: Path, ros_graph: tuple[Graph, MasterHandle], ros: Ros1
) -> None:
    graph, _ = ros_graph
    pub = graph.create_node("talker").publisher("/chatter", "std_msgs/String")
    listener = ros.start(_node(workspace, "listener"), "_count:=5")
    sent = 0

    def heard_enough() -> bool:
        nonlocal sent
        graph.executor.post(partial(pub.publish_data, {"data": f"from the graph {sent}"}))
        sent += 1
        return listener.poll() is not None

    wait_until(heard_enough, what="the C++ listener to hear 5 messages", interval=0.05)
    out, err = _finish(listener)
    lines = out.splitlines()
    assert len(lines) == 5, err
    first = int(lines[0].rsplit(" ", 1)[1].rstrip("]"))
    assert lines == [f"I heard: [from the graph {first + i}]" for i in range(5)]


def test_the_cpp_person_publisher_and_subscriber_meet_through_belvedere(
    workspace: Path, ros_graph: tuple[Graph, MasterHandle], ros: Ros1
) -> None:
    """simple.launch's pair: C++ to C++ through belvedere's master, and the graph learns
    learning_topic/Person from the publisher's connection and hears it too."""
    graph, _ = ros_graph
    subscriber = ros.start(_node(workspace, "person_subscriber"), "_count:=10")
    wait_until(
        lambda: "/person_info" in ros.run("rostopic", "list").stdout,
        what="the C++ subscriber registered",
    )
    publisher = ros.start(_node(workspace, "person_publisher"), "_count:=10")
    wait_until(lambda: _knows(graph, "learning_topic/Person"), what="learning_topic/Person learnt")
    ages: list[int] = []
    graph.executor.post(
        lambda: graph.create_node("person_listener").subscribe(
            "/person_info", "learning_topic/Person", lambda m: ages.append(m.age)
        )
    )
    out, err = _finish(subscriber)
    _finish(publisher)
    assert out.splitlines() == [
        f"Subcribe Person Info: name:Tom  age:{18 + i}  sex:1" for i in range(10)
    ], err
    assert ages == sorted(ages)
    assert all(18 <= a < 28 for a in ages)


def _knows(graph: Graph, name: str) -> bool:
    from belvedere.msgs import types

    try:
        types().resolve(name)
    except Exception:  # noqa: BLE001
        return False
    return True


def test_the_cpp_velocity_publisher_drives_a_graph_subscriber(
    workspace: Path, ros_graph: tuple[Graph, MasterHandle], ros: Ros1
) -> None:
    graph, _ = ros_graph
    commands: list[tuple[float, float]] = []
    graph.create_node("turtlesim").subscribe(
        "/turtle1/cmd_vel",
        "geometry_msgs/Twist",
        lambda m: commands.append((m.linear.x, m.angular.z)),
    )
    velocity = ros.start(_node(workspace, "velocity_publisher"), "_count:=30")
    _finish(velocity)
    wait_until(lambda: commands, what="a velocity command")
    assert set(commands) == {(0.5, 0.2)}


def test_the_graph_calls_a_cpp_service(
    workspace: Path, ros_graph: tuple[Graph, MasterHandle], ros: Ros1
) -> None:
    graph, _ = ros_graph
    server = ros.start(_node(workspace, "flag_server"))
    try:
        node = graph.create_node("caller")

        def offered() -> Any:
            return "/set_flag" in graph.services

        wait_until(offered, what="the C++ service offered on the graph")
        up = node.call_service("/set_flag", "std_srvs/SetBool", {"data": True})
        down = node.call_service("/set_flag", "std_srvs/SetBool", {"data": False})
        assert (up.success, up.message, down.success, down.message) == (
            True,
            "flag up",
            False,
            "flag down",
        )
    finally:
        server.terminate()
        server.wait(timeout=DEADLINE)


SIMPLE_LAUNCH = """\
<launch>
  <node pkg="learning_topic" type="person_subscriber" name="listener" output="screen"
        required="true">
    <param name="count" value="5"/>
  </node>
  <node pkg="learning_topic" type="person_publisher" name="talker" output="screen"/>
  <node pkg="learning_topic" type="not_built_yet" name="later"/>
</launch>
"""


def test_belvedere_launch_runs_the_courses_cpp_launch_file(
    workspace: Path, tmp_path: Path, endpoint: str
) -> None:
    """simple.launch's C++ pair started by ``belvedere launch`` with belvedere's own master
    (roslaunch's arguments, the node's private parameter), and a node the package declares
    but nobody built named once, with how to build it, while the rest runs."""
    launch = tmp_path / "simple.launch"
    launch.write_text(SIMPLE_LAUNCH)
    env = {
        **os.environ,
        "ROS_PACKAGE_PATH": str(workspace / "src"),
        "PATH": "/usr/bin:" + os.environ.get("PATH", ""),
    }
    done = subprocess.run(
        [sys.executable, "-m", "belvedere", "launch", str(launch), "--headless"],
        env=env,
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )
    heard = [line for line in done.stdout.splitlines() if line.startswith("Subcribe")]
    assert len(heard) == 5, done.stdout + done.stderr
    ages = [int(line.split("age:")[1].split()[0]) for line in heard]
    assert ages == list(range(ages[0], ages[0] + 5))
    refused = [line for line in done.stderr.splitlines() if "not_built_yet (" in line]
    assert len(refused) == 1, done.stderr
    assert "not started" in refused[0]


def test_an_unbuilt_cpp_node_is_named_with_how_to_build_it(tmp_path: Path) -> None:
    from belvedere.launch._compiled import find_compiled, unbuilt_hint

    package = tmp_path / "ws" / "src" / "learning_topic"
    package.mkdir(parents=True)
    (package / "CMakeLists.txt").write_text(
        "project(learning_topic)\nadd_executable(person_publisher src/person_publisher.cpp)\n"
    )
    assert find_compiled(package, "learning_topic", "person_publisher") is None
    hint = unbuilt_hint(package, "person_publisher")
    assert hint == (
        f"a C++ node of {package / 'CMakeLists.txt'} that is not built: "
        f"run catkin_make in {tmp_path / 'ws'}"
    )
    assert unbuilt_hint(package, "person") is None
    built = tmp_path / "ws" / "devel" / "lib" / "learning_topic" / "person_publisher"
    built.parent.mkdir(parents=True)
    built.write_bytes(b"\x7fELF")
    built.chmod(0o755)
    assert find_compiled(package, "learning_topic", "person_publisher") == built
