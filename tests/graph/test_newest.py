"""Queue size 1 means the newest message: a slow subscriber in another graph gets the last
message, never a backlog; a newest-only publisher sends the newest, never delays."""

from __future__ import annotations

import numpy as np

from belvedere.graph import Graph, ZenohTransport
from belvedere.msgs import build, types
from tests.waiting import wait_until


def _pair(endpoint: str) -> tuple[Graph, ZenohTransport, Graph, ZenohTransport]:
    sender = ZenohTransport(endpoint=endpoint, role="listen", serve_params=False)
    receiver = ZenohTransport(endpoint=endpoint, role="connect", serve_params=False)
    return (
        Graph(sim_time=False, transport=sender),
        sender,
        Graph(sim_time=False, transport=receiver),
        receiver,
    )


def test_a_slow_subscriber_gets_the_newest_message_not_a_backlog(endpoint: str) -> None:
    a, _, b, receiver = _pair(endpoint)
    try:
        newest: list[int] = []
        last_two: list[int] = []
        every: list[int] = []
        node = b.create_node("slow")
        node.subscribe("/count", "std_msgs/Int32", lambda m: newest.append(m.data), queue_size=1)
        node.subscribe("/recent", "std_msgs/Int32", lambda m: last_two.append(m.data), queue_size=2)
        node.subscribe("/all", "std_msgs/Int32", lambda m: every.append(m.data), queue_size=0)
        talker = a.create_node("talker")
        pubs = [
            talker.publisher(t, "std_msgs/Int32", queue_size=10)
            for t in ("/count", "/recent", "/all")
        ]
        wait_until(lambda: all(p.topic.remote for p in pubs), what="the subscriptions to be seen")
        for i in range(50):  # queue size 10: sent at once, none lost on the way
            for pub in pubs:
                pub.publish_data({"data": i})
        # The subscriber's executor is busy elsewhere (not spinning) while all 50 arrive.
        wait_until(
            lambda: all(receiver.stats[t].received == 50 for t in ("/count", "/recent", "/all")),
            what="50 samples on each topic",
            detail=lambda: receiver.stats,
        )
        b.spin_once()
        assert newest == [49]
        assert last_two == [48, 49]
        assert every == list(range(50))
        assert receiver.stats["/count"].skipped == 49
    finally:
        a.shutdown()
        b.shutdown()


def test_a_newest_only_publisher_ends_with_the_newest(endpoint: str) -> None:
    a, sender, b, _ = _pair(endpoint)
    try:
        got: list[int] = []
        b.create_node("rx").subscribe(
            "/frame", "sensor_msgs/Image", lambda m: got.append(m.height), queue_size=0
        )
        b.start(rtf=None)
        pub = a.create_node("camera").publisher("/frame", "sensor_msgs/Image", queue_size=1)
        commands = a.create_node("teleop").publisher("/cmd", "std_msgs/Int32", queue_size=1)
        wait_until(lambda: pub.topic.remote, what="the subscription to be seen")
        image = types().cls("sensor_msgs/Image")
        pixels = np.zeros(100 * 1000, dtype=np.uint8)  # bulky: sent newest-only
        for i in range(1, 101):
            pub.publish(image(build.header(0, "c"), i, 1000, "mono8", 0, 1000, pixels))
            commands.publish_data({"data": i})  # small: sent at once
        assert sender.flush()
        wait_until(lambda: got and got[-1] == 100, what="the newest frame", detail=lambda: got)
        assert got == sorted(set(got))  # in order, none twice
        stats = sender.stats["/frame"]
        assert stats.sent + stats.superseded == 100
        assert stats.sent == len(got)
        assert "/cmd" not in sender.stats  # nobody listens: nothing sent
    finally:
        a.shutdown()
        b.shutdown()
