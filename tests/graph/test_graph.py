"""The in-process graph: names, topics, latching, queues, timers, params, services, determinism."""

from __future__ import annotations

import hashlib
import threading
from typing import Any

import pytest

from belvedere.errors import ParseError
from belvedere.graph import Graph, GraphError, ParamError, ParamTree, parse_ros_args, resolve_name
from belvedere.graph._names import GraphNameError
from belvedere.msgs import message_from_data, types
from tests.waiting import DEADLINE, wait_until


def test_name_resolution() -> None:
    assert resolve_name("/a", namespace="/ns") == "/a"
    assert resolve_name("a", namespace="/ns") == "/ns/a"
    assert resolve_name("~a", namespace="/ns", node="n") == "/ns/n/a"
    assert resolve_name("a", namespace="/", remappings={"/a": "/b"}) == "/b"
    with pytest.raises(GraphNameError, match="segment '1x'"):
        resolve_name("/1x")


def test_ros_args() -> None:
    args = parse_ros_args(
        ["cmd_vel:=/robot/cmd_vel", "__ns:=robot", "__name:=drive", "_rate:=20", "x"]
    )
    assert args.remappings == {"cmd_vel": "/robot/cmd_vel"}
    assert (args.namespace, args.name, args.params, args.rest) == (
        "/robot",
        "drive",
        {"rate": 20},
        ["x"],
    )


def test_remapping_and_namespaces() -> None:
    g = Graph()
    got: list[str] = []
    n = g.create_node("listener", namespace="/robot", remappings={"chatter": "/global_chatter"})
    sub = n.subscribe("chatter", "std_msgs/String", lambda m: got.append(m.data))
    assert sub.name == "/global_chatter"
    g.create_node("talker").publisher("/global_chatter", "std_msgs/String").publish_data(
        {"data": "x"}
    )
    g.spin_once()
    assert got == ["x"]


def test_type_mismatch_is_an_error() -> None:
    g = Graph()
    n = g.create_node("n")
    n.publisher("/t", "std_msgs/String")
    with pytest.raises(
        GraphError, match="topic /t has type std_msgs/String; cannot also use it as std_msgs/Int32"
    ):
        n.subscribe("/t", "std_msgs/Int32", lambda m: None)
    pub = n.publisher("/t", "std_msgs/String")
    with pytest.raises(GraphError, match="publishing std_msgs/Int32 on /t"):
        pub.publish(message_from_data("std_msgs/Int32", {"data": 1}))


def test_latched_topics_reach_late_subscribers() -> None:
    g = Graph()
    n = g.create_node("n")
    n.publisher("/map", "std_msgs/String", latch=True).publish_data({"data": "m1"})
    n.publisher("/plain", "std_msgs/String").publish_data({"data": "lost"})
    got: list[str] = []
    n.subscribe("/map", "std_msgs/String", lambda m: got.append(m.data))
    n.subscribe("/plain", "std_msgs/String", lambda m: got.append(m.data))
    g.spin_once()
    assert got == ["m1"]


def test_queue_size_drops_oldest() -> None:
    g = Graph()
    n = g.create_node("n")
    got: list[int] = []
    n.subscribe("/q", "std_msgs/Int32", lambda m: got.append(m.data), queue_size=2)
    pub = n.publisher("/q", "std_msgs/Int32")
    for i in range(5):
        pub.publish_data({"data": i})
    g.spin_once()
    assert got == [3, 4]


def test_timers_in_simulated_time() -> None:
    g = Graph(sim_time=True)
    n = g.create_node("n")
    ticks: list[tuple[str, int]] = []
    n.timer(0.25, lambda: ticks.append(("slow", n.now_ns())))
    n.timer(0.1, lambda: ticks.append(("fast", n.now_ns())))
    g.run(duration=0.5)
    assert ticks == [
        ("fast", 100_000_000),
        ("fast", 200_000_000),
        ("slow", 250_000_000),
        ("fast", 300_000_000),
        ("fast", 400_000_000),
        ("slow", 500_000_000),
        ("fast", 500_000_000),
    ]
    assert g.now_ns() == 500_000_000


def _scripted_run(seed: int) -> str:
    g = Graph(sim_time=True, seed=seed)
    talker, listener = g.create_node("talker"), g.create_node("listener")
    digest = hashlib.sha256()
    pub = talker.publisher("/noise", "std_msgs/Float64")
    echo = listener.publisher("/echo", "std_msgs/Float64")
    listener.subscribe(
        "/noise", "std_msgs/Float64", lambda m: echo.publish_data({"data": m.data * 2})
    )
    listener.subscribe("/echo", "std_msgs/Float64", lambda m: digest.update(types().serialize(m)))
    talker.timer(0.01, lambda: pub.publish_data({"data": g.executor.random.gauss(0, 1)}))
    talker.timer(0.033, lambda: pub.publish_data({"data": -1.0}))
    g.run(duration=5.0)
    return digest.hexdigest()


def test_determinism_bit_for_bit() -> None:
    assert _scripted_run(1) == _scripted_run(1)
    assert _scripted_run(1) != _scripted_run(2)


def test_parameter_tree() -> None:
    p = ParamTree()
    p.load_yaml(
        "controller:\n  rate: 50\n  gains: {kp: 1.5, enabled: true}\nnames: [a, b]\n", "/robot"
    )
    assert p.get("/robot/controller/rate") == 50
    assert p.get("/robot/controller") == {"rate": 50, "gains": {"kp": 1.5, "enabled": True}}
    assert p.names("/robot") == [
        "/robot/controller/gains/enabled",
        "/robot/controller/gains/kp",
        "/robot/controller/rate",
        "/robot/names",
    ]
    p.delete("/robot/controller/gains")
    with pytest.raises(ParamError, match="parameter '/robot/controller/gains/kp' is not set"):
        p.get("/robot/controller/gains/kp")
    assert "rate: 50" in p.dump_yaml("/robot")
    with pytest.raises(ParseError, match=r"robot\.yaml:3:1: error: invalid YAML"):
        p.load_yaml("a: 1\nb: [unclosed\n", source="robot.yaml")


def test_private_params_and_node_params() -> None:
    g = Graph()
    n = g.create_node("drive", namespace="/robot", params={"rate": 20})
    assert g.params.get("/robot/drive/rate") == 20
    assert n.get_param("~rate") == 20
    assert n.get_param("~missing", 5) == 5


def test_services_in_process() -> None:
    g = Graph()
    server, client = g.create_node("server"), g.create_node("client")
    server.service("toggle", "std_srvs/SetBool", lambda req: {"success": req.data, "message": "ok"})
    response = client.call_service("/toggle", "std_srvs/SetBool", {"data": True})
    assert (response.success, response.message) == (True, "ok")
    with pytest.raises(GraphError, match="service /nope is not offered by any node"):
        client.call_service("/nope", "std_srvs/Trigger")
    with pytest.raises(
        GraphError, match="service /toggle is std_srvs/SetBool, not std_srvs/Trigger"
    ):
        client.call_service("/toggle", "std_srvs/Trigger")


def test_callback_errors_do_not_stop_the_graph(caplog: pytest.LogCaptureFixture) -> None:
    g = Graph()
    n = g.create_node("n")
    got: list[Any] = []

    def bad(msg: Any) -> None:
        text = "bug in user code"
        raise ValueError(text)

    n.subscribe("/t", "std_msgs/Int32", bad)
    n.subscribe("/t", "std_msgs/Int32", got.append)
    n.publisher("/t", "std_msgs/Int32").publish_data({"data": 1})
    g.spin_once()
    assert len(got) == 1
    assert "callback of n on /t failed" in caplog.text


def test_clock_is_published_in_simulated_time() -> None:
    g = Graph(sim_time=True, clock_hz=100)
    stamps: list[int] = []
    g.create_node("n").subscribe(
        "/clock", "rosgraph_msgs/Clock", lambda m: stamps.append(m.clock.nanosec)
    )
    g.run(duration=0.05)
    assert stamps == [10_000_000, 20_000_000, 30_000_000, 40_000_000, 50_000_000]
    assert Graph(sim_time=False).topics.get("/clock") is None


def _taken(g: Graph) -> None:
    """Returns once the graph's thread has run everything posted to it so far."""
    done = threading.Event()
    g.executor.post(done.set)
    assert done.wait(DEADLINE), "the graph's thread took nothing posted to it"


def test_pause_step_and_rtf_while_running() -> None:
    g = Graph()
    ticks: list[int] = []
    g.create_node("ticker").timer(0.1, lambda: ticks.append(g.now_ns()))
    g.executor.pause(True)
    g.start(rtf=None)
    try:
        _taken(g)
        assert g.now_ns() == 0  # paused before it began: no time passes
        g.executor.step(0.5)
        wait_until(lambda: g.now_ns() >= 500_000_000, what="the end of a 0.5 s step")
        _taken(g)
        assert g.now_ns() == 500_000_000  # exactly one step, then paused again
        assert len(ticks) == 5
        g.executor.set_rtf(1000.0)
        g.executor.pause(False)
        wait_until(lambda: g.now_ns() >= 2_000_000_000, what="2 s of simulated time")
        assert ticks == sorted(ticks)
    finally:
        g.shutdown()


def test_did_you_mean_names_the_closest_graph_names() -> None:
    from belvedere.graph import did_you_mean

    known = ["/odom", "/cmd_vel", "/odom_combined", "/scan", "/odom"]
    assert did_you_mean("/odm", known) == "did you mean /odom?"
    assert did_you_mean("/cmd_vl", known) == "did you mean /cmd_vel?"
    assert did_you_mean("/camera/image", known) is None
    assert did_you_mean("/x", []) is None


def test_every_process_names_its_clock_and_viewer_nodes_its_own() -> None:
    """Nodes each belvedere process has must not replace another process's by name when
    they share a graph (a second launch beside a simulation stopped its /clock)."""
    import os

    from belvedere.graph import process_node_name

    a, b = process_node_name("belvedere_viewer"), process_node_name("belvedere_viewer")
    assert a != b
    assert a.startswith(f"belvedere_viewer_{os.getpid()}")
    assert b.startswith(f"belvedere_viewer_{os.getpid()}_")
    graph = Graph()
    assert [n for n in graph.nodes if n.startswith(f"/belvedere_clock_{os.getpid()}")]
