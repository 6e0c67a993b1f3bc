"""A graph with a ROS 1 master, and Debian's ROS 1 tools pointed at it (or at Debian's own
roscore, the oracle)."""

from __future__ import annotations

import os
import subprocess
import textwrap
import time
import xmlrpc.client
from collections.abc import Iterator
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph, ZenohTransport
from belvedere.ros1wire import MasterHandle, start_master
from tests.conftest import free_port
from tests.debian_ros import ROSCORE, missing_debian_ros
from tests.waiting import DEADLINE


def ros_env(master_uri: str) -> dict[str, str]:
    """Debian's ROS 1 pointed at ``master_uri``: its Python and scripts first, none of ours."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "ROS_"))}
    env["PATH"] = "/usr/bin:" + env.get("PATH", "")
    env["ROS_MASTER_URI"] = master_uri
    env["ROS_HOSTNAME"] = "127.0.0.1"
    env["ROS_LOG_DIR"] = os.environ.get("ROS_LOG_DIR", "/tmp")
    return env


@dataclass
class Ros1:
    """Run Debian's ROS 1 programs against one master."""

    uri: str

    def run(self, *cmd: str, timeout: float = 30.0, stdin: str | None = None) -> Any:
        return subprocess.run(
            cmd,
            env=ros_env(self.uri),
            capture_output=True,
            text=True,
            timeout=timeout,
            input=stdin,
            check=False,
        )

    def start(self, *cmd: str) -> subprocess.Popen[str]:
        return subprocess.Popen(
            cmd,
            env=ros_env(self.uri),
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )

    def master(self) -> Any:
        return xmlrpc.client.ServerProxy(self.uri)


@pytest.fixture
def needs_debian_ros() -> None:
    why = missing_debian_ros("rospy, std_msgs.msg, rosgraph")
    if why:
        pytest.skip(why)


@pytest.fixture
def ros_graph(endpoint: str) -> Iterator[tuple[Graph, MasterHandle]]:
    """A graph holding its parameters, with a master on a free port."""
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint), clock_hz=None)
    graph.start(rtf=None)
    handle = start_master(graph, port=0)
    try:
        yield graph, handle
    finally:
        handle.close()
        graph.shutdown()


@pytest.fixture
def debian_roscore(needs_debian_ros: None) -> Iterator[Ros1]:
    """Debian's own roscore on a free port: the oracle."""
    port = free_port()
    uri = f"http://127.0.0.1:{port}/"
    proc = subprocess.Popen(
        [str(ROSCORE), "-p", str(port)],
        env=ros_env(uri),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    ros = Ros1(uri)
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                ros.master().getUri("/probe")
                break
            except OSError:
                if time.monotonic() > deadline or proc.poll() is not None:
                    pytest.fail("Debian's roscore did not start")
                time.sleep(0.1)
        yield ros
    finally:
        os.killpg(proc.pid, 2)
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, 9)
            proc.wait()


def rospy_talker(folder: Path, topic: str, count: int, words: str) -> Path:
    """A rospy script (for Debian's Python) that waits for a subscriber, then publishes
    ``"<words> 0"`` … ``"<words> count-1"`` on ``topic`` (std_msgs/String), 20 ms apart."""
    script = folder / "talker.py"
    script.write_text(
        textwrap.dedent(
            f"""
            import rospy
            from std_msgs.msg import String
            rospy.init_node("ros1_talker")
            pub = rospy.Publisher({topic!r}, String, queue_size=100)
            while pub.get_num_connections() == 0 and not rospy.is_shutdown():
                rospy.sleep(0.05)
            rospy.sleep(0.3)
            for i in range({count}):
                pub.publish(String(data="{words} %d" % i))
                rospy.sleep(0.02)
            rospy.sleep(0.5)
            """
        )
    )
    return script


def publish_until(graph: Graph, pub: Any, done: Any, make: Any, period: float = 0.02) -> None:
    """Publish ``make(i)`` every ``period`` seconds (on the executor) until ``done()``."""
    i = 0
    deadline = time.monotonic() + DEADLINE
    while not done() and time.monotonic() < deadline:
        graph.executor.post(partial(pub.publish_data, make(i)))
        i += 1
        time.sleep(period)
