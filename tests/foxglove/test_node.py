"""foxglove_bridge as a launch node: the include of ``$(find foxglove_bridge)/launch/
foxglove_bridge.launch`` (or a ``<node>``) serves the launch's graph, with the bridge's
``port``, ``address`` and ``topic_whitelist``; bad parameters are one error at the node's line."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest
import websockets.exceptions

from belvedere.errors import BelvedereError
from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from tests.conftest import free_port
from tests.foxglove.client import FoxgloveClient


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


def test_an_address_beyond_this_machine_needs_the_logged_token(
    graph: Graph, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    # 127.0.0.1 stands for another address here (tests stay on loopback)
    monkeypatch.setattr("belvedere.access.is_loopback", lambda host: host == "localhost")
    port = free_port()
    with caplog.at_level(logging.INFO, logger="belvedere.launch"):
        runtime = _launch(
            graph,
            tmp_path / "fox.launch",
            "<launch>\n"
            '  <node pkg="foxglove_bridge" type="foxglove_bridge" name="fox">\n'
            f'    <param name="port" value="{port}"/>\n'
            '    <param name="address" value="127.0.0.1"/>\n'
            "  </node>\n"
            "</launch>\n",
        )
    try:
        (record,) = (r for r in caplog.records if "token" in r.getMessage())
        assert record.levelno == logging.WARNING
        text = record.getMessage()
        assert text.startswith("/fox: serving beyond this machine on 127.0.0.1: Foxglove clients")
        url = text.rsplit(" ", 1)[1]
        assert url.startswith(f"ws://127.0.0.1:{port}/?token=")
        with pytest.raises(websockets.exceptions.InvalidStatus):
            FoxgloveClient(f"ws://127.0.0.1:{port}")
        FoxgloveClient(url).close()
    finally:
        runtime.close()
