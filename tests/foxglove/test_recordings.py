"""Recordings of ``belvedere bag record`` carry what Foxglove needs to open them: for MCAP,
schemas of a known encoding (``ros2msg``) that describe the messages (``cdr``) whole, and a
summary with chunk indexes (Foxglove seeks by them); for ROS 1 bags, each connection's type,
MD5 sum and full message definition, and the index."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from rosbags.rosbag1 import Reader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from belvedere.foxglove import ros1_schema
from belvedere.graph import Graph, ZenohTransport
from tests.foxglove.test_bridge import BEAMS, _talker, plain
from tests.waiting import DEADLINE

HOUR_NS = 3600 * 1_000_000_000
TOPICS = {
    "/scan": "sensor_msgs/msg/LaserScan",
    "/cmd_vel": "geometry_msgs/msg/Twist",
    "/clock": "rosgraph_msgs/msg/Clock",
}


@pytest.fixture(scope="module")
def recordings(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """One second of a simulation (a scan at 10 Hz, a Twist at 20 Hz), recorded by
    ``belvedere bag record -a`` in a process of its own, as MCAP and as a ROS 1 bag."""
    from tests.conftest import free_endpoint

    tmp = tmp_path_factory.mktemp("recordings")
    env = {"BELVEDERE_ENDPOINT": free_endpoint(), "BELVEDERE_DOMAIN": "231"}
    with pytest.MonkeyPatch.context() as patch:
        for key, value in env.items():
            patch.setenv(key, value)
        graph = Graph(sim_time=True, transport=ZenohTransport())
        try:
            _talker(graph)
            graph.start(rtf=2.0)
            for ext in ("mcap", "bag"):
                record = ["bag", "record", "-a", "-O", f"run.{ext}", "--duration", "1"]
                done = subprocess.run(
                    [sys.executable, "-m", "belvedere", *record],
                    cwd=tmp,
                    capture_output=True,
                    text=True,
                    timeout=DEADLINE,
                    check=False,
                )
                assert done.returncode == 0, done.stderr
        finally:
            graph.shutdown()
    return {"mcap": tmp / "run.mcap", "bag": tmp / "run.bag"}


def test_a_recorded_mcap_has_what_foxglove_reads(recordings: dict[str, Path]) -> None:
    mcap_reader = pytest.importorskip("mcap.reader")
    with recordings["mcap"].open("rb") as f:
        reader = mcap_reader.make_reader(f, validate_crcs=True)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        assert summary is not None
        assert summary.chunk_indexes
        channels = {c.topic: c for c in summary.channels.values()}
        assert set(TOPICS) <= set(channels)
        for topic, msgtype in TOPICS.items():
            channel = channels[topic]
            assert channel.message_encoding == "cdr"
            schema = summary.schemas[channel.schema_id]
            assert (schema.name, schema.encoding) == (msgtype, "ros2msg")
            # the schema alone describes the messages, as Foxglove reads them
            found = get_types_from_msg(schema.data.decode(), msgtype)
            assert msgtype in found
        stats = summary.statistics
        assert stats.message_count == sum(stats.channel_message_counts.values())
        assert stats.channel_message_counts[channels["/scan"].id] >= 9
        scan_schema = summary.schemas[channels["/scan"].schema_id]
        store = get_typestore(Stores.EMPTY)
        store.register(get_types_from_msg(scan_schema.data.decode(), TOPICS["/scan"]))
        scans = [
            (m.log_time, plain(store.deserialize_cdr(m.data, TOPICS["/scan"])))
            for _, c, m in reader.iter_messages(topics=["/scan"])
        ]
    assert all(
        len(s["ranges"]) == BEAMS and s["header"]["frame_id"] == "laser_link" for _, s in scans
    )
    # log times in the simulation's time: each scan's own stamp
    for log_time, s in scans:
        stamp = s["header"]["stamp"]
        assert log_time == stamp["sec"] * 1_000_000_000 + stamp["nanosec"] < HOUR_NS


def test_a_recorded_ros1_bag_has_what_foxglove_reads(recordings: dict[str, Path]) -> None:
    with Reader(recordings["bag"]) as bag:
        connections = {c.topic: c for c in bag.connections}
        assert set(TOPICS) <= set(connections)
        assert bag.chunk_infos  # the index Foxglove seeks by
        for topic, msgtype in TOPICS.items():
            conn = connections[topic]
            ros1_name, text = ros1_schema(msgtype)
            assert conn.msgtype == msgtype
            assert conn.msgdef.data == text  # what the Foxglove bridge advertises, too
            assert msgtype in get_types_from_msg(conn.msgdef.data, ros1_name)
        assert connections["/scan"].digest == "90c7ef2dc6895d81024acba2ac42f369"
        assert connections["/cmd_vel"].digest == "9f195f881246fdfa2798d1d3eebca84a"
        assert bag.message_count >= 9 + 19
