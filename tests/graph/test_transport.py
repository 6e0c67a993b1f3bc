"""Two processes on loopback exchange every kind of traffic."""

from __future__ import annotations

import logging
import time
from typing import Any

import pytest

from belvedere.graph import Graph, GraphError, Sent, ZenohTransport
from belvedere.graph._zenoh_latch import _STAMP
from belvedere.graph._zenoh_session import open_session
from belvedere.msgs import message_from_data, types
from tests.waiting import DEADLINE, wait_until


def test_traffic_between_processes(peer: Any, endpoint: str) -> None:
    transport = ZenohTransport(endpoint=endpoint, serve_params=False)
    assert transport.role == "connect"  # the peer listens; we connect
    g = Graph(sim_time=False, transport=transport)
    n = g.create_node("tester")
    ticks: list[str] = []
    latched: list[str] = []
    echoed: list[float] = []
    n.subscribe("/chatter", "std_msgs/String", lambda m: ticks.append(m.data))
    n.subscribe("/map_name", "std_msgs/String", lambda m: latched.append(m.data))
    n.subscribe("/cmd_echo", "geometry_msgs/Twist", lambda m: echoed.append(m.linear.x))
    cmd = n.publisher("/cmd_vel", "geometry_msgs/Twist")
    g.start(rtf=None)
    try:
        wait_until(lambda: len(ticks) >= 3, what="3 messages on /chatter from the peer")
        # latched: we subscribed after it was sent
        wait_until(lambda: latched, what="the latched /map_name")
        assert latched == ["office"]
        # a second subscription here gets it too (and the first not again)
        again: list[str] = []
        n.subscribe("/map_name", "std_msgs/String", lambda m: again.append(m.data))
        wait_until(lambda: again, what="the latched /map_name for a second subscription")
        assert again == ["office"]
        assert latched == ["office"]
        wait_until(lambda: cmd.topic.remote, what="the peer to subscribe to /cmd_vel")
        for i in range(20):
            cmd.publish_data({"linear": {"x": float(i)}})
        wait_until(lambda: len(echoed) >= 20, what="20 echoes on /cmd_echo", detail=lambda: echoed)
        assert echoed == [float(i) for i in range(20)]  # BLOCK: nothing lost, in order
        response = n.call_service("/trigger", "std_srvs/Trigger", timeout=DEADLINE)
        assert (response.success, response.message) == (True, "done")
        assert transport.param_request({"op": "get", "name": "/robot/speed"}) == 0.5
        transport.param_request({"op": "set", "name": "/robot/mode", "value": {"a": [1, 2]}})
        assert transport.param_request({"op": "get", "name": "/robot"}) == {
            "speed": 0.5,
            "mode": {"a": [1, 2]},
        }
        with pytest.raises(GraphError, match="parameter '/nope' is not set"):
            transport.param_request({"op": "get", "name": "/nope"})
        info = transport.info()
        assert {"/peer", "/tester"} <= info.nodes
        assert info.topic_type("/chatter") == "std_msgs/msg/String"
        assert ("std_srvs/srv/Trigger", "/peer") in info.services["/trigger"]
        with pytest.raises(GraphError, match="service /absent is not offered by any node"):
            n.call_service("/absent", "std_srvs/Trigger", timeout=0.5)
    finally:
        g.shutdown()


def test_nothing_is_serialized_without_remote_subscribers(endpoint: str) -> None:
    g = Graph(sim_time=True, transport=ZenohTransport(endpoint=endpoint))
    pub = g.create_node("n").publisher("/lonely", "std_msgs/String")
    assert not pub.topic.remote
    g.shutdown()


def test_default_is_localhost_without_scouting(endpoint: str) -> None:
    session, role = open_session(endpoint)
    try:
        assert role == "listen"
        locators = (
            [str(loc) for loc in session.info.locators()]
            if hasattr(session.info, "locators")
            else []
        )
        assert all("127.0.0.1" in loc for loc in locators)
    finally:
        session.close()  # type: ignore[no-untyped-call]


def test_own_latched_messages_arrive_once(endpoint: str) -> None:
    """A process's latched message reaches its later subscriptions once each: from the graph,
    not again from its own Zenoh queryable."""
    g = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    n = g.create_node("n")
    n.publisher("/x", "std_msgs/String", latch=True).publish_data({"data": "hi"})
    got: list[tuple[str, str]] = []
    n.subscribe("/x", "std_msgs/String", lambda m: got.append(("first", m.data)))
    g.start(rtf=None)
    try:
        wait_until(lambda: got, what="the latched /x")
        g.executor.post(
            lambda: n.subscribe("/x", "std_msgs/String", lambda m: got.append(("second", m.data)))
        )
        wait_until(lambda: len(got) >= 2, what="the latched /x for the second subscription")
        # the queryable's answer would come within the fetch's 2 s: wait them out
        g.executor.post(lambda: got.append(("mark", "")))
        wait_until(lambda: ("mark", "") in got, what="the executor")
        time.sleep(2.5)
    finally:
        g.shutdown()
    assert sorted(got) == [("first", "hi"), ("mark", ""), ("second", "hi")]


def test_who_publishes_a_topic_across_graphs(peer: Any, endpoint: str) -> None:
    transport = ZenohTransport(endpoint=endpoint, serve_params=False)
    graph = Graph(sim_time=False, transport=transport)
    try:
        graph.create_node("mine").publisher("/chatter", "std_msgs/String")
        # the peer process publishes /chatter too; nobody publishes /nothing
        wait_until(
            lambda: transport.publisher_nodes("/chatter") == {"/mine", "/peer"},
            what="both publishers of /chatter",
        )
        assert transport.publisher_nodes("/nothing") == set()
        assert transport.service_offered("/trigger")
        assert not transport.service_offered("/nothing")
    finally:
        graph.shutdown()


def test_a_graph_follows_the_clock_of_a_running_simulation(endpoint: str) -> None:
    """A graph that joins a simulation takes its time from /clock: its timers fire as that
    clock passes them, its time never runs ahead of the simulation's, and a run's duration
    counts from the first time the clock reads."""
    sim = Graph(sim_time=True, transport=ZenohTransport(endpoint=endpoint))
    sim.start(rtf=4.0)
    try:
        wait_until(lambda: sim.now_ns() > 300_000_000, what="the simulation at 0.3 s")
        joined = Graph(
            sim_time=True,
            clock_hz=None,
            transport=ZenohTransport(endpoint=endpoint, serve_params=False),
        )
        fired: list[tuple[int, int]] = []
        clocks: list[int] = []
        node = joined.create_node("follower")
        joined.follow_clock(node)
        node.subscribe("/clock", "rosgraph_msgs/Clock", lambda m: clocks.append(joined.now_ns()))
        node.timer(0.5, lambda: fired.append((joined.now_ns(), sim.now_ns())), oneshot=True)
        assert joined.executor.following
        assert joined.executor.horizon_ns() == 0
        try:
            joined.run(duration=1.0)
        finally:
            joined.shutdown()
    finally:
        sim.shutdown()
    mine, theirs = fired[0]
    assert 500_000_000 <= mine <= theirs
    assert clocks[0] > 300_000_000
    assert joined.now_ns() >= clocks[0] + 1_000_000_000
    wall = Graph(sim_time=False)
    with pytest.raises(GraphError, match="only a graph in simulated time can follow /clock"):
        wall.follow_clock(wall.create_node("x"))


def test_a_topic_of_another_type_on_the_graph_is_refused(peer: Any, endpoint: str) -> None:
    """The peer process subscribes to /cmd_vel as a Twist and publishes /chatter as a String:
    a node here that would use them as something else is refused, naming both types (ROS 1
    would connect them and drop every message)."""
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    try:
        node = graph.create_node("mine")
        with pytest.raises(
            GraphError,
            match=r"topic /cmd_vel has type geometry_msgs/Twist \(/peer subscribes to it\); "
            r"cannot publish std_msgs/String on it$",
        ):
            node.publisher("/cmd_vel", "std_msgs/String")
        with pytest.raises(
            GraphError,
            match=r"topic /chatter has type std_msgs/String \(/peer publishes it\); "
            r"cannot subscribe to it as geometry_msgs/Twist$",
        ):
            node.subscribe("/chatter", "geometry_msgs/Twist", lambda m: None)
        assert "/cmd_vel" not in {p.name for p in node.publishers}
        # the same types are welcome
        assert node.publisher("/cmd_vel", "geometry_msgs/Twist").topic.type == (
            "geometry_msgs/msg/Twist"
        )
    finally:
        graph.shutdown()


def test_messages_of_another_type_are_dropped_with_one_warning_per_publisher(
    endpoint: str, caplog: pytest.LogCaptureFixture
) -> None:
    """A publisher of another type that came before the check could see it (two processes
    starting at once) reaches a subscriber: its messages are dropped unread, with one warning
    per publisher naming both types and its node; the right type still arrives."""
    listener = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
    got: list[float] = []
    listener.create_node("sim").subscribe(
        "/cmd_vel", "geometry_msgs/Twist", lambda m: got.append(m.linear.x)
    )
    listener.start(rtf=None)
    # What a racing publisher's messages are on the wire: a String's bytes, typed and signed.
    racer = ZenohTransport(endpoint=endpoint, serve_params=False)
    string = types().serialize(message_from_data("std_msgs/String", {"data": "hi"}))
    twist = types().serialize(message_from_data("geometry_msgs/Twist", {"linear": {"x": 1.0}}))
    key = racer._key("t", "/cmd_vel")
    try:
        with caplog.at_level(logging.WARNING, logger="belvedere.transport"):
            for sender in ("/racer", "/racer", "/other_racer") * 10:
                attachment = _STAMP.pack(b"w", 0) + f"std_msgs/msg/String\n{sender}".encode()
                racer.session.put(key, string, attachment=attachment)
            # a peer that says nothing about its messages, sending what is not a Twist
            for _ in range(5):
                racer.session.put(key, string)
            racer.session.put(key, twist, attachment=_STAMP.pack(b"w", 0))
            wait_until(lambda: got, what="the Twist after the Strings")
        warnings = [r.getMessage() for r in caplog.records]
    finally:
        racer.close()
        listener.shutdown()
    assert got == [1.0]
    assert warnings[:2] == [
        "topic types do not match on /cmd_vel: [geometry_msgs/Twist] here vs. "
        "[std_msgs/String] from /racer; its messages are dropped",
        "topic types do not match on /cmd_vel: [geometry_msgs/Twist] here vs. "
        "[std_msgs/String] from /other_racer; its messages are dropped",
    ]
    assert len(warnings) == 3
    assert warnings[2].startswith("dropping messages on /cmd_vel that are not geometry_msgs/Twist:")


def test_a_tap_and_a_question_name_the_same_latched_publication(endpoint: str) -> None:
    """A recorder may hear a latched message through its tap and in the reply to its question
    for latched messages, in either order: both name the publication (its publisher and its
    number), so it is recorded once; a new publication has a higher number."""
    listener = ZenohTransport(endpoint=endpoint)
    tapped: list[tuple[bytes, Sent]] = []
    tap = listener.tap("/cmd_vel", lambda _topic, data, t: tapped.append((data, t)))
    talker = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
    pub = talker.create_node("driver").publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    talker.start(rtf=None)
    try:
        pub.publish_data({"linear": {"x": 0.2}})
        wait_until(lambda: tapped, what="the tapped message")
        asked = wait_until(lambda: listener.latched_raw("/cmd_vel"), what="the latched reply")
        pub.publish_data({"linear": {"x": 0.3}})
        wait_until(lambda: len(tapped) == 2, what="the second message")
    finally:
        tap.undeclare()
        talker.shutdown()
        listener.close()
    (data, first), (_, second) = tapped
    assert [(raw, sent.latch) for raw, sent in asked] == [(data, first.latch)]
    assert first.latch is not None
    assert second.latch is not None
    assert first.latch[0] == second.latch[0]
    assert second.latch[1] > first.latch[1]


def test_a_latched_message_reaches_the_subscribers_that_were_there_first(endpoint: str) -> None:
    """As ROS 1 sends a latched message on every new connection: a publisher that starts
    after the subscriber and publishes at once reaches it, also when its process had not yet
    heard of the subscriber (the message went nowhere then), and exactly once."""
    transport = ZenohTransport(endpoint=endpoint)
    listener = Graph(sim_time=False, transport=transport)
    got: list[str] = []
    listener.create_node("listener").subscribe(
        "/map_name", "std_msgs/String", lambda m: got.append(m.data)
    )
    raw: list[bytes] = []  # as a recorder sees them: not one sent twice
    tap = transport.tap("/map_name", lambda _topic, data, _sent: raw.append(data))
    listener.start(rtf=None)
    try:
        for i in range(8):
            talker = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
            node = talker.create_node("talker")
            talker.start(rtf=None)
            try:
                node.publisher("/map_name", "std_msgs/String", latch=True).publish_data(
                    {"data": f"map {i}"}
                )
                wait_until(lambda i=i: f"map {i}" in got, what=f"latched message {i}")  # type: ignore[misc]
            finally:
                talker.shutdown()
        time.sleep(1.0)  # a second copy (the resent one) would come within this
    finally:
        tap.undeclare()
        listener.shutdown()
    assert got == [f"map {i}" for i in range(8)]
    assert len(raw) == 8


def test_a_process_whose_last_subscription_left_is_sent_nothing(endpoint: str) -> None:
    """Zenoh's subscriber goes with the process's last subscription on a topic, so publishers
    elsewhere stop sending (and this process stops decoding) what nobody here reads; a new
    subscription brings it back."""
    listener = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
    talker = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
    pub = talker.create_node("talker").publisher("/chatter", "std_msgs/String")
    node = listener.create_node("listener")
    got: list[str] = []
    listener.start(rtf=None)
    talker.start(rtf=None)
    try:
        subs = [node.subscribe("/chatter", "std_msgs/String", lambda m: got.append(m.data))]
        subs.append(node.subscribe("/chatter", "std_msgs/String", lambda m: None))
        wait_until(lambda: pub.topic.remote, what="the talker seeing the listener")
        subs[0].unregister()
        time.sleep(0.5)  # one subscription is left: the talker still sends
        assert pub.topic.remote
        subs[1].unregister()
        wait_until(lambda: not pub.topic.remote, what="the talker seeing nobody")
        node.subscribe("/chatter", "std_msgs/String", lambda m: got.append(m.data))
        wait_until(lambda: pub.topic.remote, what="the talker seeing the listener again")
        pub.publish_data({"data": "again"})
        wait_until(lambda: got == ["again"], what="the message on the new subscription")
    finally:
        talker.shutdown()
        listener.shutdown()
