"""Interoperability: bags belvedere writes open in ROS 1's rosbag (its Python API and its
``info`` and ``reindex`` commands) and in rosbags; bags ROS 1's rosbag writes read and play
in belvedere."""

from __future__ import annotations

import json
import os
import subprocess
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.bags import Decoder, Player, PlayOptions, create_writer, info_text, open_bag
from belvedere.bags._model import encode
from belvedere.graph import Graph
from tests.bags._make import MS, odometry, scan, write_sample
from tests.debian_ros import ROS_PYTHON, missing_debian_ros

ORACLE = Path(__file__).with_name("rosbag_oracle.py")
ROSBAG = Path("/usr/bin/rosbag")
MISSING = missing_debian_ros("rosbag, geometry_msgs.msg, std_msgs.msg")

needs_rosbag = pytest.mark.skipif(MISSING is not None, reason=MISSING or "")


def _oracle(*args: str) -> Any:
    env = {**os.environ, "PATH": f"/usr/bin:{os.environ.get('PATH', '')}", "TZ": "UTC"}
    env.pop("PYTHONPATH", None)
    done = subprocess.run(
        [str(ROS_PYTHON), str(ORACLE), *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout) if args[0] == "read" else None


def _rosbag(*args: str) -> subprocess.CompletedProcess[str]:
    if not ROSBAG.exists():
        pytest.skip(f"{ROSBAG} is not installed")
    env = {**os.environ, "PATH": f"/usr/bin:{os.environ.get('PATH', '')}", "TZ": "UTC"}
    env.pop("PYTHONPATH", None)
    return subprocess.run(
        [str(ROSBAG), *args], capture_output=True, text=True, env=env, timeout=120, check=False
    )


@needs_rosbag
@pytest.mark.oracle
@pytest.mark.parametrize("compression", ["none", "lz4", "bz2"])
def test_rosbag_reads_our_bags(tmp_path: Path, compression: str) -> None:
    path = tmp_path / "ours.bag"
    write_sample(path, compression=compression, flush_every=60)
    seen = _oracle("read", str(path))
    by_topic: dict[str, list[dict[str, Any]]] = {}
    for m in seen["messages"]:
        by_topic.setdefault(m["topic"], []).append(m)
    assert {t: len(v) for t, v in by_topic.items()} == {"/map_name": 1, "/odom": 200, "/scan": 20}
    for i, m in enumerate(by_topic["/odom"]):
        want = odometry(i)
        assert m["t"] == (i + 1) * 10 * MS
        assert m["fields"] == {
            "seq": i,
            "stamp": [want.header.stamp.sec, want.header.stamp.nanosec],
            "frame_id": "odom",
            "child_frame_id": "base_footprint",
            "x": want.pose.pose.position.x,
            "y": want.pose.pose.position.y,
            "wz": 0.5,
        }
    assert by_topic["/scan"][3]["fields"]["ranges"] == pytest.approx(scan(3).ranges.tolist())
    assert by_topic["/map_name"][0]["fields"] == {"data": "cloister"}
    headers = {h["topic"]: h for h in seen["connections"]}
    assert headers["/map_name"]["latching"] == "1"
    assert headers["/map_name"]["callerid"] == "/map_server"
    assert headers["/odom"]["latching"] == "0"
    assert headers["/odom"]["md5sum"] == "cd5e73d190d741a2f92e81eda573aca7"
    assert headers["/odom"]["type"] == "nav_msgs/Odometry"


@needs_rosbag
@pytest.mark.oracle
@pytest.mark.parametrize(("compression", "flag"), [("none", []), ("lz4", ["--lz4"])])
def test_rosbag_info_prints_what_we_print(
    tmp_path: Path, utc: None, compression: str, flag: list[str]
) -> None:
    path = tmp_path / "ours.bag"
    write_sample(path, compression=compression, flush_every=50)
    theirs = _rosbag("info", str(path))
    assert theirs.returncode == 0, theirs.stderr
    bag = open_bag(path)
    ours = info_text(bag)
    bag.close()
    assert ours == theirs.stdout.rstrip("\n")
    del flag


@needs_rosbag
@pytest.mark.oracle
def test_rosbag_reindex_and_ours_agree_on_a_killed_recording(tmp_path: Path) -> None:
    active = tmp_path / "rec.bag.active"
    writer = create_writer(active)
    odom = writer.add_connection("/odom", "nav_msgs/msg/Odometry", callerid="/g", latching=False)
    sizes = []
    for i in range(160):
        writer.write(odom, (i + 1) * 10 * MS, encode(odometry(i), "ros1"))
        if i % 40 == 39:
            writer.flush()
            sizes.append(active.stat().st_size)
    # killed while writing the fourth chunk: the file ends in its middle
    cut = (sizes[2] + sizes[3]) // 2
    theirs, ours = tmp_path / "theirs.bag", tmp_path / "ours.bag"
    for copy in (theirs, ours):
        copy.write_bytes(active.read_bytes()[:cut])
    writer.close()
    done = _rosbag("reindex", str(theirs))
    assert done.returncode == 0, done.stderr
    from belvedere.bags import reindex

    reindex(ours)
    a, b = _oracle("read", str(theirs)), _oracle("read", str(ours))
    assert len(a["messages"]) == 120
    assert a["messages"] == b["messages"]
    mine = open_bag(theirs)  # what ROS 1 repaired reads here too
    assert sum(mine.counts.values()) == 120
    mine.close()


@needs_rosbag
@pytest.mark.oracle
@pytest.mark.parametrize("compression", ["none", "lz4", "bz2"])
def test_bags_rosbag_writes_read_and_play_here(tmp_path: Path, utc: None, compression: str) -> None:
    path = tmp_path / "theirs.bag"
    _oracle("write", str(path), compression)
    bag = open_bag(path)
    conns = {c.topic: c for c in bag.connections}
    assert conns["/map_name"].latching
    assert conns["/map_name"].callerid == "/map_server"
    theirs = _rosbag("info", str(path))
    assert info_text(bag) == theirs.stdout.rstrip("\n")

    graph = Graph(sim_time=True)
    got: dict[str, list[Any]] = {"/pose": [], "/cmd_vel": [], "/map_name": []}
    listener = graph.create_node("listener")
    for topic, kind in (
        ("/pose", "geometry_msgs/PoseStamped"),
        ("/cmd_vel", "geometry_msgs/Twist"),
        ("/map_name", "std_msgs/String"),
    ):
        listener.subscribe(topic, kind, partial(_keep, got[topic], graph), queue_size=0)
    player = Player(graph.create_node("play"), PlayOptions(bags=(path,), clock=True), bags=[bag])
    player.start()
    graph.run(rtf=None, until=player.done.is_set)
    bag.close()
    assert [len(v) for v in got.values()] == [50, 5, 1]
    for i, (when, pose) in enumerate(got["/pose"]):
        assert when == 1_700_000_000 * 10**9 + i * 20 * MS  # the graph's time is the bag's
        assert pose.header.seq == i
        assert pose.pose.position.x == i * 0.5
    assert got["/cmd_vel"][2][1].linear.x == pytest.approx(2.0)
    assert graph.topics["/map_name"].publishers[0].latch


def _keep(into: list[Any], graph: Graph, msg: Any) -> None:
    into.append((graph.now_ns(), msg))


def test_rosbags_reads_our_mcap_files(tmp_path: Path) -> None:
    from rosbags.highlevel import AnyReader
    from rosbags.interfaces import ConnectionExtRosbag2, QosDurability
    from rosbags.typesys import Stores, get_typestore

    for compression in ("none", "lz4"):
        path = tmp_path / f"ours-{compression}.mcap"
        write_sample(path, compression=compression, flush_every=70)
        store = get_typestore(Stores.ROS1_NOETIC)  # belvedere's layouts (Header with seq)
        with AnyReader([path], default_typestore=store) as reader:
            seen: list[tuple[str, int, Any]] = [
                (c.topic, t, reader.deserialize(raw, c.msgtype)) for c, t, raw in reader.messages()
            ]
            durability = {}
            for c in reader.connections:
                assert isinstance(c.ext, ConnectionExtRosbag2)
                durability[c.topic] = c.ext.offered_qos_profiles[0].durability
        odom = [(t, m) for topic, t, m in seen if topic == "/odom"]
        assert len(odom) == 200
        assert len(seen) == 221
        t, m = odom[123]
        assert t == 124 * 10 * MS
        assert m.header.seq == 123
        assert m.pose.pose.position.y == odometry(123).pose.pose.position.y
        assert durability["/map_name"] == QosDurability.TRANSIENT_LOCAL
        assert durability["/odom"] == QosDurability.VOLATILE
        reference = Decoder().decode(next(iter(open_bag(path).messages())))
        assert reference.data == "cloister"


def test_mcap_package_reads_our_files(tmp_path: Path) -> None:
    """Foxglove's reader (the mcap package) takes our files: chunk CRCs, indexes, summary."""
    mcap_reader = pytest.importorskip("mcap.reader")
    for compression in ("none", "lz4"):
        path = tmp_path / f"ours-{compression}.mcap"
        write_sample(path, compression=compression, flush_every=70)
        with path.open("rb") as f:
            reader = mcap_reader.make_reader(f, validate_crcs=True)
            assert reader.get_header().profile == "ros2"
            summary = reader.get_summary()
            assert summary is not None
            assert summary.statistics.message_count == 221
            assert len(summary.chunk_indexes) == 3  # flushed after 70 and 140, and closed
            schemas = {s.name: s for s in summary.schemas.values()}
            assert schemas["nav_msgs/msg/Odometry"].encoding == "ros2msg"
            channels = {c.topic: c for c in summary.channels.values()}
            assert channels["/odom"].message_encoding == "cdr"
            assert channels["/odom"].metadata["callerid"] == "/gazebo"
            seen = [(c.topic, m.log_time, m.data) for _, c, m in reader.iter_messages()]
            ours = [(m.connection.topic, m.stamp_ns, m.data) for m in open_bag(path).messages()]
            assert seen == ours
    # a recording killed outright, recovered: whole again for the mcap package too
    active = tmp_path / "rec.mcap.active"
    writer = create_writer(active)
    odom = writer.add_connection("/odom", "nav_msgs/msg/Odometry", callerid="/g", latching=False)
    for i in range(90):
        writer.write(odom, (i + 1) * 10 * MS, encode(odometry(i), writer.encoding))
        if i == 59:
            writer.flush()
    killed = tmp_path / "killed.mcap"
    killed.write_bytes(active.read_bytes() + b"\x06\x00\x10")
    writer.close()
    from belvedere.bags import reindex

    reindex(killed)
    with killed.open("rb") as f:
        reader = mcap_reader.make_reader(f, validate_crcs=True)
        assert sum(1 for _ in reader.iter_messages()) == 60
        assert reader.get_summary().statistics.message_count == 60


def test_ros2_mcap_files_play_here(tmp_path: Path) -> None:
    """An MCAP file of ROS 2's layouts (rosbags' rosbag2 writer, Humble's types: a Header
    without seq) reads into belvedere's types, field by field."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    humble = get_typestore(Stores.ROS2_HUMBLE)
    odometry_cls = humble.types["nav_msgs/msg/Odometry"]
    header_cls = humble.types["std_msgs/msg/Header"]
    time_cls = humble.types["builtin_interfaces/msg/Time"]
    out = tmp_path / "ros2bag"
    with Writer(out, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conn = writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=humble)
        for i in range(20):
            msg = odometry_cls(
                header=header_cls(stamp=time_cls(sec=3, nanosec=i * 1000), frame_id="odom"),
                child_frame_id="base_link",
                pose=humble.types["geometry_msgs/msg/PoseWithCovariance"](
                    pose=humble.types["geometry_msgs/msg/Pose"](
                        position=humble.types["geometry_msgs/msg/Point"](x=i * 1.5, y=0.0, z=0.0),
                        orientation=humble.types["geometry_msgs/msg/Quaternion"](
                            x=0.0, y=0.0, z=0.0, w=1.0
                        ),
                    ),
                    covariance=np.zeros(36),
                ),
                twist=humble.types["geometry_msgs/msg/TwistWithCovariance"](
                    twist=humble.types["geometry_msgs/msg/Twist"](
                        linear=humble.types["geometry_msgs/msg/Vector3"](x=0.5, y=0.0, z=0.0),
                        angular=humble.types["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                    ),
                    covariance=np.zeros(36),
                ),
            )
            writer.write(conn, 1_000 + i * 10 * MS, humble.serialize_cdr(msg, conn.msgtype))
    (mcap,) = out.glob("*.mcap")
    bag = open_bag(mcap)
    decoder = Decoder()
    got = [decoder.decode(m) for m in bag.messages()]
    bag.close()
    assert len(got) == 20
    assert got[7].__msgtype__ == "nav_msgs/msg/Odometry"
    assert got[7].header.seq == 0  # ROS 2 has none
    assert (got[7].header.stamp.sec, got[7].header.stamp.nanosec) == (3, 7000)
    assert got[7].header.frame_id == "odom"
    assert got[7].child_frame_id == "base_link"
    assert got[7].pose.pose.position.x == 7 * 1.5
    assert got[7].twist.twist.linear.x == 0.5


def test_ros1_profile_mcap_files_play_here(tmp_path: Path) -> None:
    """MCAP of the ros1 profile (as ``mcap convert`` makes from a ROS 1 bag): ROS 1 bytes
    under ros1msg schemas, latching in the channel's metadata."""
    mcap_writer = pytest.importorskip("mcap.writer")
    from belvedere.bags._model import ros1_definition

    path = tmp_path / "ros1.mcap"
    with path.open("wb") as f:
        writer = mcap_writer.Writer(f)
        writer.start(profile="ros1")
        name, md5, text = ros1_definition("nav_msgs/msg/Odometry")
        schema = writer.register_schema(name, "ros1msg", text.encode())
        odom = writer.register_channel("/odom", "ros1", schema, {"md5sum": md5, "latching": "0"})
        name, md5, text = ros1_definition("std_msgs/msg/String")
        schema = writer.register_schema(name, "ros1msg", text.encode())
        latched = writer.register_channel("/map_name", "ros1", schema, {"latching": "1"})
        writer.add_message(latched, 1, encode(_string("office"), "ros1"), 1)
        for i in range(30):
            stamp = (i + 1) * 10 * MS
            writer.add_message(odom, stamp, encode(odometry(i), "ros1"), stamp, i)
        writer.finish()
    bag = open_bag(path)
    assert bag.version == "MCAP (ros1 profile)"
    conns = {c.topic: c for c in bag.connections}
    assert conns["/map_name"].latching
    assert conns["/odom"].encoding == "ros1"
    graph = Graph(sim_time=True)
    got: list[tuple[int, Any]] = []
    graph.create_node("l").subscribe(
        "/odom", "nav_msgs/Odometry", partial(_keep, got, graph), queue_size=0
    )
    player = Player(graph.create_node("play"), PlayOptions(bags=(path,), clock=True), bags=[bag])
    player.start()
    graph.run(rtf=None, until=player.done.is_set)
    bag.close()
    assert [when for when, _ in got] == [(i + 1) * 10 * MS for i in range(30)]
    assert got[12][1].pose.pose.position.x == odometry(12).pose.pose.position.x
    assert graph.topics["/map_name"].publishers[0].latch


def _string(text: str) -> Any:
    from belvedere.msgs import message_from_data

    return message_from_data("std_msgs/String", {"data": text})
