"""The Foxglove bridge, spoken to as the Foxglove app speaks to it: channels with ROS 1
schemas, messages that ROS 1's deserializer reads back as they were published, stamped with
the graph's (simulated) time, subscriptions on the graph only while a client wants them,
topics that come and go, a client's publishing and the parameters."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from belvedere.foxglove import FoxgloveBridge
from belvedere.graph import Graph, Node
from tests.foxglove.client import FoxgloveClient
from tests.waiting import wait_until

BEAMS = 360
PI32 = float(np.float32(np.pi))


def plain(value: Any) -> Any:
    """A message as nested builtins, whichever type store made it."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = (f.name for f in dataclasses.fields(value) if not f.name.startswith("__"))
        return {name: plain(getattr(value, name)) for name in fields}
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, list | tuple):
        return [plain(v) for v in value]
    return value


def ros1_decoder(channel: dict[str, Any]) -> Callable[[bytes], Any]:
    """Decode a channel's messages as Foxglove does: from its schema alone."""
    name = channel["schemaName"]
    found = get_types_from_msg(channel["schema"], name)
    store = get_typestore(Stores.EMPTY)
    store.register(found)
    full = next(iter(found))  # the schema's own type comes first
    return lambda data: store.deserialize_ros1(data, full)


@pytest.fixture
def client(bridge: FoxgloveBridge) -> Iterator[FoxgloveClient]:
    c = FoxgloveClient(bridge.url)
    yield c
    c.close()


def _talker(graph: Graph) -> Node:
    """Publishes a Twist at 20 Hz and a 360-beam LaserScan at 10 Hz, each one different."""
    node = graph.create_node("talker")
    twist = node.publisher("/cmd_vel", "geometry_msgs/Twist")
    scan = node.publisher("/scan", "sensor_msgs/LaserScan")
    count = [0, 0]

    def send_twist() -> None:
        count[0] += 1
        twist.publish_data({"linear": {"x": 0.1 * count[0]}, "angular": {"z": -0.5}})

    def send_scan() -> None:
        count[1] += 1
        sec, nsec = graph.clock_stamp()
        ranges = (np.arange(BEAMS, dtype=np.float32) + count[1]) / 100
        scan.publish_data(
            {
                "header": {"frame_id": "laser_link", "stamp": {"secs": sec, "nsecs": nsec}},
                # float32 fields get values float32 holds exactly: the wire has float32
                "angle_min": -PI32,
                "angle_max": PI32,
                "angle_increment": float(np.float32(2 * PI32 / BEAMS)),
                "range_max": 8.0,
                "ranges": ranges.tolist(),
                "intensities": [float(count[1])] * BEAMS,
            }
        )

    node.timer(0.05, send_twist)
    node.timer(0.1, send_scan)
    return node


def _listen(graph: Graph, topic: str, msgtype: str) -> list[tuple[int, Any]]:
    """What a subscriber on the graph receives, with the graph's time then."""
    seen: list[tuple[int, Any]] = []
    graph.create_node(f"listener{len(graph.nodes)}").subscribe(
        topic, msgtype, lambda m: seen.append((graph.now_ns(), plain(m))), queue_size=0
    )
    return seen


def test_channels_carry_ros1_schemas_and_messages_in_graph_time(
    graph: Graph, bridge: FoxgloveBridge, client: FoxgloveClient
) -> None:
    _talker(graph)
    twists = _listen(graph, "/cmd_vel", "geometry_msgs/Twist")
    scans = _listen(graph, "/scan", "sensor_msgs/LaserScan")
    graph.start(rtf=2.0)
    assert client.subprotocol == "foxglove.sdk.v1"
    assert "time" in client.server_info["capabilities"]
    assert "clientPublish" in client.server_info["capabilities"]
    twist_channel = client.channel("/cmd_vel")
    scan_channel = client.channel("/scan")
    for channel, name in (
        (twist_channel, "geometry_msgs/Twist"),
        (scan_channel, "sensor_msgs/LaserScan"),
    ):
        assert channel["encoding"] == "ros1"
        assert channel["schemaEncoding"] == "ros1msg"
        assert channel["schemaName"] == name
    assert "MSG: std_msgs/Header" in scan_channel["schema"]
    assert "MSG: geometry_msgs/Vector3" in twist_channel["schema"]
    assert client.channel("/clock")["schemaName"] == "rosgraph_msgs/Clock"

    twist_sub = client.subscribe("/cmd_vel")
    scan_sub = client.subscribe("/scan")
    client.wait(lambda: len(client.received(scan_sub)) >= 5, what="five scans")
    client.wait(lambda: len(client.received(twist_sub)) >= 10, what="ten twists")
    for sub, channel, published in (
        (twist_sub, twist_channel, twists),
        (scan_sub, scan_channel, scans),
    ):
        decode = ros1_decoder(channel)
        got = [(m.log_time, plain(decode(m.data))) for m in client.received(sub)]
        # each message as the graph's subscribers received it, at the graph's time then
        for item in got:
            assert item in published
        stamps = [t for t, _ in got]
        assert stamps == sorted(stamps)
        assert len(set(stamps)) == len(stamps)
    scan = plain(ros1_decoder(scan_channel)(client.received(scan_sub)[0].data))
    assert len(scan["ranges"]) == BEAMS
    assert scan["header"]["frame_id"] == "laser_link"
    # simulated time: the log time is the scan's own stamp (taken when it was published)
    first = client.received(scan_sub)[0]
    stamp = scan["header"]["stamp"]
    assert first.log_time == stamp["sec"] * 1_000_000_000 + stamp["nanosec"]
    # the server's time is the graph's (simulated, from 0), moving on with the messages
    last = client.received(scan_sub)[-1].log_time
    client.wait(lambda: client.times and client.times[-1] >= last, what="the server's time")
    assert client.times == sorted(client.times)
    assert client.times[-1] < 3600 * 1_000_000_000


def test_the_graph_is_subscribed_only_while_a_client_is(
    graph: Graph, bridge: FoxgloveBridge, client: FoxgloveClient
) -> None:
    _talker(graph)
    graph.start(rtf=2.0)
    topic = graph.topics["/scan"]

    def bridge_subscribed() -> bool:
        return any(s.node is bridge.node for s in list(topic.subscriptions))

    client.channel("/scan")
    assert not bridge_subscribed()
    sub = client.subscribe("/scan")
    wait_until(bridge_subscribed, what="the bridge to subscribe to /scan")
    client.wait(lambda: client.received(sub), what="a scan")
    # a second client: both get the messages; one leaving keeps the subscription
    other = FoxgloveClient(bridge.url)
    try:
        other_sub = other.subscribe("/scan")
        other.wait(lambda: other.received(other_sub), what="a scan for the second client")
        other.unsubscribe(other_sub)
        count = len(client.received(sub))
        client.wait(lambda: len(client.received(sub)) > count + 2, what="more scans")
        assert bridge_subscribed()
    finally:
        other.close()
    client.unsubscribe(sub)
    wait_until(lambda: not bridge_subscribed(), what="the bridge to unsubscribe from /scan")


def test_topics_that_appear_later_are_advertised_and_those_that_go_withdrawn(
    graph: Graph, bridge: FoxgloveBridge, client: FoxgloveClient
) -> None:
    graph.start(rtf=1.0)
    node = graph.create_node("late")
    pub = node.publisher("/status", "std_msgs/String", latch=True)
    pub.publish_data({"data": "ready"})
    channel = client.channel("/status")
    assert channel["schemaName"] == "std_msgs/String"
    assert channel["schema"] == "string data\n"
    # a latched message reaches a client that subscribes after it was published
    sub = client.subscribe("/status")
    message = client.wait(lambda: client.received(sub), what="the latched message")[0]
    assert plain(ros1_decoder(channel)(message.data)) == {"data": "ready"}
    graph.executor.post(pub.unregister)
    client.wait(lambda: channel["id"] in client.withdrawn, what="/status to be withdrawn")
    assert "/status" not in bridge.topics()


def test_a_client_publishes_on_the_graph_in_ros1_and_json(
    graph: Graph, bridge: FoxgloveBridge, client: FoxgloveClient
) -> None:
    received = _listen(graph, "/cmd_vel", "geometry_msgs/Twist")
    graph.start(rtf=1.0)
    noetic = get_typestore(Stores.ROS1_NOETIC)
    twist = noetic.types["geometry_msgs/msg/Twist"]
    vector = noetic.types["geometry_msgs/msg/Vector3"]
    cid = client.advertise("/cmd_vel", "ros1", "geometry_msgs/Twist")
    data = noetic.serialize_ros1(
        twist(vector(0.25, 0.0, 0.0), vector(0.0, 0.0, 1.5)), twist.__msgtype__
    )
    client.publish(cid, bytes(data))
    wait_until(lambda: received, what="the client's Twist on the graph")
    assert received[0][1] == {
        "linear": {"x": 0.25, "y": 0.0, "z": 0.0},
        "angular": {"x": 0.0, "y": 0.0, "z": 1.5},
    }
    # the same topic in JSON, from another client channel
    cid_json = client.advertise("/cmd_vel", "json", "geometry_msgs/Twist")
    client.publish(cid_json, b'{"linear": {"x": -0.5}}')
    wait_until(lambda: len(received) >= 2, what="the JSON Twist")
    assert received[1][1]["linear"]["x"] == -0.5
    # a message that is not what the channel said: one status naming the topic
    client.publish(cid, b"\x01")
    client.wait(lambda: client.statuses, what="a status")
    assert client.statuses[0]["level"] == 2
    assert "/cmd_vel" in client.statuses[0]["message"]
    assert "Twist" in client.statuses[0]["message"]
    # the graph's type wins: a client cannot publish another type on /cmd_vel
    wrong = client.advertise("/cmd_vel", "ros1", "std_msgs/String")
    client.publish(wrong, b"\x00\x00\x00\x00")
    client.wait(lambda: len(client.statuses) >= 2, what="a second status")
    assert "geometry_msgs/Twist" in client.statuses[1]["message"]
    assert len(received) == 2


def test_parameters_are_read_and_set(
    graph: Graph, bridge: FoxgloveBridge, client: FoxgloveClient
) -> None:
    graph.params.set("/robot/max_speed", 0.5)
    graph.params.set("/robot/name", "mbot")
    graph.params.set("/robot/joints", ["left", "right"])
    graph.start(rtf=1.0)
    values = {p["name"]: p["value"] for p in client.get_parameters([])}
    assert values["/robot/max_speed"] == 0.5
    assert values["/robot/name"] == "mbot"
    assert values["/robot/joints"] == ["left", "right"]
    assert values["/use_sim_time"] is True
    assert client.get_parameters(["/robot/name"]) == [{"name": "/robot/name", "value": "mbot"}]
    changed = client.set_parameters({"/robot/max_speed": 0.75})
    assert [(p["name"], p["value"]) for p in changed] == [("/robot/max_speed", 0.75)]
    assert graph.params.get("/robot/max_speed") == 0.75
