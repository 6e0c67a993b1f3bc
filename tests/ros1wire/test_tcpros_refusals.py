"""What a publisher answers a subscriber it refuses — a wrong type or MD5, a topic it does
not publish — from belvedere's bridge as from a roscpp publisher (the course's C++ talker,
built with Debian's catkin), the same texts; and a subscriber that only speaks UDPROS, which
belvedere lacks as rospy does, answered as a rospy publisher answers it."""

from __future__ import annotations

import re
import socket
import xmlrpc.client
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.ros1wire import MasterHandle
from belvedere.ros1wire._tcpros import read_header, write_header
from tests.debian_ros import ROS_PYTHON
from tests.ros1wire.catkin import PACKAGE, build_workspace, missing_catkin
from tests.ros1wire.conftest import Ros1, rospy_talker
from tests.waiting import wait_until

pytestmark = pytest.mark.usefixtures("needs_debian_ros")

INT32_MD5 = "da5909fbe378aeaf85e547e830cc1bb7"
STRING_MD5 = "992ce8a1687cec8c8bd883ec73ca41d1"


@pytest.fixture(scope="module")
def workspace() -> Path:
    why = missing_catkin()
    if why:
        pytest.skip(why)
    return build_workspace()


def _publisher_api(ros: Ros1, node: str) -> Any:
    code, _, uri = ros.master().lookupNode("/probe", node)
    assert code == 1, uri
    return xmlrpc.client.ServerProxy(uri)


def _udpros(api: Any) -> list[Any]:
    """requestTopic from a subscriber that speaks only UDPROS."""
    answer: list[Any] = api.requestTopic("/probe", "/chatter", [["UDPROS"]])
    return answer


def _answers(api: Any) -> dict[str, str]:
    """The connection headers' errors a publisher sends back for a wrong type, a wrong MD5
    and a topic it does not publish (port and socket numbers left out)."""
    out: dict[str, str] = {}
    code, _, (_, host, port) = api.requestTopic("/probe", "/chatter", [["TCPROS"]])
    assert code == 1
    asks = {
        "type": {"type": "std_msgs/Int32", "md5sum": INT32_MD5, "topic": "/chatter"},
        "md5": {"type": "std_msgs/String", "md5sum": INT32_MD5, "topic": "/chatter"},
        "topic": {"type": "std_msgs/String", "md5sum": STRING_MD5, "topic": "/nothing"},
    }
    for case, fields in asks.items():
        with socket.create_connection((host, port), timeout=10) as sock:
            write_header(sock, {"callerid": "/probe", "tcp_nodelay": "0", **fields})
            out[case] = re.sub(
                r"(?<=port )\d+|(?<=:)\d+(?= on)|(?<=socket )\d+",
                "N",
                read_header(sock).get("error", ""),
            )
    return out


@pytest.fixture
def belvedere(ros_graph: tuple[Graph, MasterHandle]) -> Any:
    """The publisher API of a graph node publishing /chatter, through the bridge."""
    graph, handle = ros_graph
    graph.create_node("talker").publisher("/chatter", "std_msgs/String")
    ros = Ros1(handle.uri)
    wait_until(lambda: "/talker" in ros.run("rosnode", "list").stdout.split(), what="/talker")
    return _publisher_api(ros, "/talker")


@pytest.fixture
def roscpp(workspace: Path, debian_roscore: Ros1) -> Iterator[dict[str, str]]:
    talker = debian_roscore.start(str(workspace / "devel" / "lib" / PACKAGE / "talker"))
    try:
        wait_until(
            lambda: "/talker" in debian_roscore.run("rosnode", "list").stdout.split(),
            what="the C++ talker",
        )
        yield _answers(_publisher_api(debian_roscore, "/talker"))
    finally:
        talker.terminate()
        talker.communicate(timeout=30)


def test_refusals_are_roscpps(roscpp: dict[str, str], belvedere: Any) -> None:
    ours = _answers(belvedere)
    assert ours == roscpp
    assert ours["md5"].startswith("Client [/probe] wants topic /chatter to have datatype/md5sum")


def test_a_udpros_subscriber_is_answered_as_rospy_answers_it(
    belvedere: Any, debian_roscore: Ros1, tmp_path: Path
) -> None:
    talker = debian_roscore.start(
        str(ROS_PYTHON), str(rospy_talker(tmp_path, "/chatter", 1, "hello"))
    )
    try:
        wait_until(
            lambda: "/ros1_talker" in debian_roscore.run("rosnode", "list").stdout.split(),
            what="the rospy talker",
        )
        rospy_answer = _udpros(_publisher_api(debian_roscore, "/ros1_talker"))
    finally:
        talker.kill()
        talker.communicate(timeout=30)
    assert _udpros(belvedere) == rospy_answer == [0, "no supported protocol implementations", []]
