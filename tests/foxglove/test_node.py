"""foxglove_bridge as a launch node: the include of ``$(find foxglove_bridge)/launch/
foxglove_bridge.launch`` (or a ``<node>``) serves the launch's graph, with the bridge's
``port``, ``address`` and ``topic_whitelist``; bad parameters are one error at the node's line."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from belvedere.errors import BelvedereError
from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from tests.conftest import free_port
from tests.foxglove.client import FoxgloveClient


@pytest.fixture
def graph() -> Iterator[Graph]:
    g = Graph(sim_time=True)
    yield g
    g.shutdown()


def _launch(graph: Graph, path: Path, text: str) -> LaunchRuntime:
    path.write_text(text)
    packages = PackageIndex([path.parent])
    runtime = LaunchRuntime(load_launch(path, packages=packages), graph, packages, headless=True)
    runtime.start()
    return runtime


def test_the_included_bridge_serves_the_whitelisted_topics(graph: Graph, tmp_path: Path) -> None:
    port = free_port()
    runtime = _launch(
        graph,
        tmp_path / "fox.launch",
        "<launch>\n"
        '  <include file="$(find foxglove_bridge)/launch/foxglove_bridge.launch">\n'
        f'    <arg name="port" value="{port}"/>\n'
        "    <arg name=\"topic_whitelist\" value=\"['/odom.*', '/rosout']\"/>\n"
        "  </include>\n"
        "</launch>\n",
    )
    talker = graph.create_node("talker")
    odom = talker.publisher("/odom", "nav_msgs/Odometry")
    chatter = talker.publisher("/chatter", "std_msgs/String")
    talker.timer(0.1, lambda: (odom.publish_data({}), chatter.publish_data({"data": "hi"})))
    graph.start(rtf=1.0)
    client = FoxgloveClient(f"ws://127.0.0.1:{port}")
    try:
        client.channel("/odom")
        sub = client.subscribe("/odom")
        client.wait(lambda: client.received(sub), what="odometry through the bridge")
        topics = {c["topic"] for c in client.channels.values()}
        assert "/chatter" not in topics  # not whitelisted
        assert topics <= {"/odom", "/rosout"}
    finally:
        client.close()
        runtime.close()


@pytest.mark.parametrize(
    ("param", "message"),
    [
        ('<param name="port" value="seventy"/>', r"~port: expected a port number"),
        (
            '<rosparam param="topic_whitelist">[1, 2]</rosparam>',
            r"~topic_whitelist: expected a list of regular expressions",
        ),
        (
            '<rosparam param="topic_whitelist">["(unclosed"]</rosparam>',
            r"topic_whitelist: '\(unclosed' is not a regular expression",
        ),
    ],
)
def test_bad_parameters_are_one_error_at_the_node(
    graph: Graph, tmp_path: Path, param: str, message: str
) -> None:
    with pytest.raises(BelvedereError, match=message) as err:
        _launch(
            graph,
            tmp_path / "bad.launch",
            "<launch>\n"
            '  <node pkg="foxglove_bridge" type="foxglove_bridge" name="fox">\n'
            f"    {param}\n"
            '    <param name="port" type="int" value="0"/>\n'
            "  </node>\n"
            "</launch>\n"
            if "port" not in param
            else "<launch>\n"
            '  <node pkg="foxglove_bridge" type="foxglove_bridge" name="fox">\n'
            f"    {param}\n"
            "  </node>\n"
            "</launch>\n",
        )
    location = err.value.describe()
    assert "bad.launch:2:" in location, location
