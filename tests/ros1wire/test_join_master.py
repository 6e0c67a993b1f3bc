"""``--ros-master``: the graph joins Debian's own roscore, as a robot's, and its nodes and
rospy's meet there both ways."""

from __future__ import annotations

import subprocess
import sys
import time
from functools import partial
from pathlib import Path

import pytest

from belvedere.graph import Graph, ZenohTransport
from belvedere.ros1wire import RemoteMasterError, join_master
from tests.conftest import free_port
from tests.debian_ros import ROS_PYTHON
from tests.ros1wire.conftest import Ros1, rospy_talker
from tests.waiting import DEADLINE, wait_until


def test_the_graph_joins_a_running_roscore(
    debian_roscore: Ros1, endpoint: str, tmp_path: Path
) -> None:
    debian_roscore.run("rosparam", "set", "/robot_description", "<robot name='r'/>")
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint), clock_hz=None)
    graph.start(rtf=None)
    handle = join_master(graph, debian_roscore.uri)
    try:
        assert graph.params.get("/robot_description") == "<robot name='r'/>"
        node = graph.create_node("laptop")
        heard: list[str] = []
        node.subscribe("/chatter", "std_msgs/String", lambda m: heard.append(m.data))
        odom = node.publisher("/laptop_odom", "std_msgs/String")
        node.service(
            "laptop_ping", "std_srvs/Trigger", lambda r: {"success": True, "message": "pong"}
        )
        talker = debian_roscore.start(
            str(ROS_PYTHON), str(rospy_talker(tmp_path, "/chatter", 20, "robot"))
        )
        assert talker.wait(timeout=DEADLINE) == 0
        wait_until(lambda: len(heard) >= 20, what="20 messages from rospy", detail=lambda: heard)
        assert heard == [f"robot {i}" for i in range(20)]
        echo = debian_roscore.start("rostopic", "echo", "-n", "1", "/laptop_odom")

        def heard_by_rostopic() -> bool:
            graph.executor.post(partial(odom.publish_data, {"data": "here"}))
            return echo.poll() is not None

        wait_until(heard_by_rostopic, what="rostopic echo to hear the graph", interval=0.1)
        assert echo.communicate()[0] == 'data: "here"\n---\n'
        called = debian_roscore.run("rosservice", "call", "/laptop_ping")
        assert called.stdout == 'success: True\nmessage: "pong"\n', called.stderr
        assert "/laptop_odom" in debian_roscore.run("rostopic", "list").stdout.split()
    finally:
        handle.close()
        graph.shutdown()
    wait_until(
        lambda: "/laptop_odom" not in debian_roscore.run("rostopic", "list").stdout.split(),
        what="the graph's publisher unregistered",
    )


def test_belvedere_topic_echo_with_ros_master(debian_roscore: Ros1, tmp_path: Path) -> None:
    echo = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "belvedere",
            "topic",
            "echo",
            "/chatter",
            "-n",
            "3",
            "--ros-master",
            debian_roscore.uri,
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    time.sleep(1.0)
    talker = debian_roscore.start(
        str(ROS_PYTHON), str(rospy_talker(tmp_path, "/chatter", 200, "robot"))
    )
    try:
        out, err = echo.communicate(timeout=DEADLINE)
    finally:
        talker.kill()
        echo.kill()
    values = [line for line in out.splitlines() if line.startswith("data:")]
    assert len(values) == 3, out + err
    first = int(values[0].split()[-1].rstrip('"'))
    assert values == [f'data: "robot {first + i}"' for i in range(3)]


def test_a_master_that_is_not_there_is_one_error(endpoint: str) -> None:
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint), clock_hz=None)
    try:
        with pytest.raises(RemoteMasterError, match="cannot reach the ROS 1 master at"):
            join_master(graph, f"http://127.0.0.1:{free_port()}")
    finally:
        graph.shutdown()
