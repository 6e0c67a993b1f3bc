"""The bridge's frames against Foxglove's own server (foxglove-sdk), the reference of the
protocol: the same conversation with each gives the same server info, channel
advertisements, message data and time frames, parameter values and statuses."""

from __future__ import annotations

import json
import struct
import threading
from collections.abc import Iterator
from typing import Any

import pytest
from websockets.sync.client import ClientConnection, connect

from belvedere.foxglove import FoxgloveBridge, ros1_schema
from belvedere.graph import Graph
from belvedere.msgs import types
from tests.foxglove.client import SUBPROTOCOLS
from tests.waiting import DEADLINE

foxglove = pytest.importorskip("foxglove")
pytestmark = pytest.mark.oracle

PARAMS: dict[str, Any] = {
    "/p/float": 0.5,
    "/p/int": 3,
    "/p/text": "mbot",
    "/p/flag": True,
    "/p/floats": [1.0, 2.5],
    "/p/mixed": [1, "x"],
}


class Frames:
    """One connection, read frame by frame."""

    def __init__(self, url: str) -> None:
        self.ws: ClientConnection = connect(
            url, subprotocols=list(SUBPROTOCOLS), proxy=None, open_timeout=DEADLINE
        )

    def next(self, want: str | int) -> Any:
        """The next JSON frame of op ``want`` (or binary frame of opcode ``want``)."""
        while True:
            frame = self.ws.recv(timeout=DEADLINE)
            if isinstance(frame, bytes):
                if frame[0] == want:
                    return frame
            else:
                doc = json.loads(frame)
                if doc["op"] == want:
                    return doc

    def send(self, op: str, **fields: Any) -> None:
        self.ws.send(json.dumps({"op": op, **fields}))


class _ParamListener:
    def __init__(self) -> None:
        self.subscribed = threading.Event()

    def on_subscribe(self, client: Any, channel: Any) -> None:
        self.subscribed.set()

    def on_unsubscribe(self, client: Any, channel: Any) -> None:
        pass

    def on_get_parameters(self, client: Any, names: list[str], request_id: Any = None) -> Any:
        values = [_sdk_parameter(n, v) for n, v in PARAMS.items()]
        return [p for p in values if not names or p.name in names]


def _sdk_parameter(name: str, value: Any) -> Any:
    kind = None
    if isinstance(value, float):
        kind = foxglove.ParameterType.Float64
    elif isinstance(value, list) and all(isinstance(v, float) for v in value):
        kind = foxglove.ParameterType.Float64Array
    return foxglove.Parameter(name, value=value, type=kind)


@pytest.fixture
def reference() -> Iterator[tuple[Any, Any, _ParamListener]]:
    from foxglove.websocket import Capability

    context = foxglove.Context()
    listener = _ParamListener()
    server = foxglove.start_server(
        name="belvedere",
        host="127.0.0.1",
        port=0,
        context=context,
        server_listener=listener,
        capabilities=[Capability.Time, Capability.ClientPublish, Capability.Parameters],
        supported_encodings=["ros1", "json"],
    )
    name, text = ros1_schema("std_msgs/msg/String")
    channel = foxglove.Channel(
        "/chatter",
        schema=foxglove.Schema(name=name, encoding="ros1msg", data=text.encode()),
        message_encoding="ros1",
        context=context,
    )
    yield server, channel, listener
    server.stop()


@pytest.fixture
def ours() -> Iterator[tuple[Graph, FoxgloveBridge]]:
    graph = Graph(sim_time=True, clock_hz=None)
    for name, value in PARAMS.items():
        graph.params.set(name, value)
    graph.params.delete("/use_sim_time")
    node = graph.create_node("talker")
    pub = node.publisher("/chatter", "std_msgs/String", latch=True)
    pub.publish_data({"data": "hello"})
    bridge = FoxgloveBridge(graph, port=0)
    yield graph, bridge
    bridge.close()
    graph.shutdown()


def _shape(doc: dict[str, Any]) -> dict[str, Any]:
    """A frame without what differs by design (who made it, when)."""
    return {k: v for k, v in doc.items() if k not in ("metadata", "sessionId")}


def test_the_same_conversation_gives_the_same_frames(
    reference: tuple[Any, Any, _ParamListener], ours: tuple[Graph, FoxgloveBridge]
) -> None:
    server, channel, listener = reference
    graph, bridge = ours
    graph.start(rtf=1.0)
    theirs = Frames(f"ws://127.0.0.1:{server.port}")
    mine = Frames(bridge.url)
    assert theirs.ws.subprotocol == mine.ws.subprotocol == "foxglove.sdk.v1"

    info = [_shape(f.next("serverInfo")) for f in (theirs, mine)]
    assert set(info[0]) == set(info[1])
    assert set(info[0]["capabilities"]) == set(info[1]["capabilities"])
    assert info[0]["supportedEncodings"] == info[1]["supportedEncodings"]

    advertised = []
    for frames in (theirs, mine):
        doc = frames.next("advertise")
        while not any(c["topic"] == "/chatter" for c in doc["channels"]):
            doc = frames.next("advertise")
        advertised.append(next(c for c in doc["channels"] if c["topic"] == "/chatter"))
    assert set(advertised[0]) == set(advertised[1])
    for key in ("topic", "encoding", "schemaName", "schemaEncoding", "schema"):
        assert advertised[0][key] == advertised[1][key]

    # a subscription's message data: opcode, the client's subscription id, log time, payload
    for frames, found in zip((theirs, mine), advertised, strict=True):
        frames.send("subscribe", subscriptions=[{"id": 42, "channelId": found["id"]}])
    payload = bytes(types().store.serialize_ros1(_string("hello"), "std_msgs/msg/String"))
    # (the reference drops what is logged before the subscription reaches its table)
    assert listener.subscribed.wait(DEADLINE)
    channel.log(payload, log_time=1_500_000_000)
    data = [f.next(0x01) for f in (theirs, mine)]
    for frame in data:
        opcode, sub, _ = struct.unpack_from("<BIQ", frame)
        assert (opcode, sub) == (1, 42)
        assert frame[13:] == payload
    assert struct.unpack_from("<Q", data[0], 5)[0] == 1_500_000_000

    # the server's time: opcode 2 and a uint64
    server.broadcast_time(7)
    times = [f.next(0x02) for f in (theirs, mine)]
    assert [len(t) for t in times] == [9, 9]
    assert struct.unpack("<BQ", times[0]) == (2, 7)

    # parameters, typed alike
    for frames in (theirs, mine):
        frames.send("getParameters", parameterNames=sorted(PARAMS), id="q")
    values = [f.next("parameterValues") for f in (theirs, mine)]
    assert values[0]["id"] == values[1]["id"] == "q"
    by_name = [sorted(v["parameters"], key=lambda p: p["name"]) for v in values]
    assert by_name[0] == by_name[1]

    # a status: the same shape and, for an unknown channel, the same text
    for frames in (theirs, mine):
        frames.send("subscribe", subscriptions=[{"id": 7, "channelId": 999}])
    statuses = [f.next("status") for f in (theirs, mine)]
    assert set(statuses[0]) == set(statuses[1])
    assert statuses[0]["level"] == statuses[1]["level"] == 2
    assert statuses[0]["message"] == statuses[1]["message"] == "Unknown channel ID: 999"

    theirs.ws.close()
    mine.ws.close()


def _string(text: str) -> Any:
    return types().store.types["std_msgs/msg/String"](data=text)
