"""Fuzzing a live Foxglove bridge with malformed client messages: valid requests with hostile
fields, mutated JSON text and random binary frames. After each example's frames the same
connection must still answer a request (so nothing it sent stopped the bridge or that
client), the graph must still run, and the bridge must have logged no error of its own (an
exception in the bridge is logged as one and answered "internal error")."""

from __future__ import annotations

import json
import logging
import struct
from collections.abc import Iterator
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st
from websockets.sync.client import connect
from websockets.sync.connection import Connection

from belvedere.foxglove import FoxgloveBridge
from belvedere.graph import Graph
from tests.foxglove.client import SUBPROTOCOLS
from tests.fuzz._mutate import HOSTILE_NUMBERS, Mutation, fuzz_settings, mutations, text_mutant
from tests.waiting import DEADLINE


class _Errors(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.ERROR)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.records.append(record)


ERRORS = _Errors()


@pytest.fixture(scope="module")
def bridge() -> Iterator[FoxgloveBridge]:
    logger = logging.getLogger("belvedere.foxglove")
    logger.addHandler(ERRORS)
    graph = Graph(sim_time=True)
    node = graph.create_node("talker")
    pub = node.publisher("/chatter", "std_msgs/String")
    node.timer(0.1, lambda: pub.publish_data({"data": "hi"}))
    graph.params.set("/robot/speed", 0.5)
    graph.start(rtf=1.0)
    b = FoxgloveBridge(graph, port=0)
    yield b
    b.close()
    graph.shutdown()
    logger.removeHandler(ERRORS)


SEEDS: tuple[dict[str, Any], ...] = (
    {"op": "subscribe", "subscriptions": [{"id": 1, "channelId": 1}]},
    {"op": "unsubscribe", "subscriptionIds": [1]},
    {
        "op": "advertise",
        "channels": [
            {"id": 1, "topic": "/fuzz", "encoding": "json", "schemaName": "std_msgs/String"}
        ],
    },
    {"op": "unadvertise", "channelIds": [1]},
    {"op": "getParameters", "parameterNames": ["/robot/speed"], "id": "a"},
    {"op": "setParameters", "parameters": [{"name": "/fuzz/p", "value": 1.5}], "id": "b"},
    {
        "op": "setParameters",
        "parameters": [{"name": "/fuzz/q", "value": [1, 2], "type": "float64_array"}],
    },
    {"op": "subscribeParameterUpdates", "parameterNames": ["/robot/speed"]},
    {"op": "unsubscribeParameterUpdates", "parameterNames": []},
)

json_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(min_value=-(2**70), max_value=2**70)
    | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(max_size=12)
    | st.sampled_from(["", "/", "/a b", "~x", "ros1", "json", "std_msgs/String", "float64"]),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner),
    max_leaves=12,
)


def _paths(doc: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Every place in a JSON document a value can be replaced."""
    found = [prefix] if prefix else []
    if isinstance(doc, dict):
        for key, value in doc.items():
            found += _paths(value, (*prefix, key))
    elif isinstance(doc, list):
        for i, value in enumerate(doc):
            found += _paths(value, (*prefix, i))
    return found


def _replace(doc: Any, path: tuple[Any, ...], value: Any) -> Any:
    if not path:
        return value
    copy = json.loads(json.dumps(doc))
    target = copy
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    return copy


@st.composite
def hostile_field(draw: st.DrawFn) -> str:
    seed = draw(st.sampled_from(SEEDS))
    path = draw(st.sampled_from(_paths(seed)))
    return json.dumps(_replace(seed, path, draw(json_values)))


TOKENS = (*HOSTILE_NUMBERS, "[", "]", "{", "}", ",", ":", '"', "NaN", "null", "\\u0000", "[" * 50)


@st.composite
def mutated_text(draw: st.DrawFn) -> str:
    seed = json.dumps(draw(st.sampled_from(SEEDS)))
    edits: list[Mutation] = draw(mutations())
    return text_mutant(seed, edits, TOKENS)


binary = st.one_of(
    st.binary(max_size=24),
    st.builds(
        lambda op, channel, tail: struct.pack("<BI", op, channel) + tail,
        st.sampled_from([0, 1, 2, 3, 255]),
        st.sampled_from([0, 1, 2, 0xFFFFFFFF]) | st.integers(0, 0xFFFFFFFF),
        st.binary(max_size=16),
    ),
)
frames = st.lists(hostile_field() | mutated_text() | binary, min_size=1, max_size=6)


def _answers(ws: Connection) -> bool:
    """The connection still serves: a request of ours gets its reply."""
    ws.send(json.dumps({"op": "getParameters", "parameterNames": [], "id": "probe"}))
    while True:
        frame = ws.recv(timeout=DEADLINE)
        if isinstance(frame, str):
            doc = json.loads(frame)
            if doc["op"] == "parameterValues" and doc.get("id") == "probe":
                return True


@fuzz_settings(150)
@given(frames)
def test_foxglove_client_mutants(bridge: FoxgloveBridge, sent: list[str | bytes]) -> None:
    with connect(bridge.url, subprotocols=list(SUBPROTOCOLS), proxy=None) as ws:
        for frame in sent:
            ws.send(frame)
        assert _answers(ws)
    thread = bridge.graph.executor.thread
    assert thread is not None
    assert thread.is_alive()
    assert not ERRORS.records, [r.getMessage() for r in ERRORS.records]
