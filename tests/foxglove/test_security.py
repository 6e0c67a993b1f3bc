"""Who may use the Foxglove bridge, and what one client's bad input does: a page of a foreign
origin is refused at the handshake, a bridge beyond this machine wants its token, and a
malformed client message is an error status to that client while the bridge serves on."""

from __future__ import annotations

import json
import socket
import struct

import pytest
import websockets.exceptions
from websockets.sync.client import connect

from belvedere.access import ServerAccess
from belvedere.cli import main
from belvedere.foxglove import FOXGLOVE_APP, FoxgloveBridge, FoxgloveBridgeError
from belvedere.graph import Graph
from tests.foxglove.client import SUBPROTOCOLS, FoxgloveClient
from tests.waiting import DEADLINE, wait_until


def refused(url: str, *, origin: str | None) -> str:
    """The handshake is refused with HTTP 403: the reason given."""
    with pytest.raises(websockets.exceptions.InvalidStatus) as caught:
        connect(
            url,
            origin=origin,  # type: ignore[arg-type]
            subprotocols=list(SUBPROTOCOLS),
            proxy=None,
            open_timeout=DEADLINE,
        ).close()
    response = caught.value.response
    assert response.status_code == 403
    return response.body.decode()


def raw_handshake(port: int, *, host: str, origin: str) -> str:
    """A handshake with any ``Host`` (a DNS-rebound page's): the whole answer."""
    with socket.create_connection(("127.0.0.1", port), timeout=DEADLINE) as s:
        s.sendall(
            (
                f"GET / HTTP/1.1\r\nHost: {host}\r\nOrigin: {origin}\r\n"
                "Upgrade: websocket\r\nConnection: Upgrade\r\n"
                "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
                f"Sec-WebSocket-Protocol: {SUBPROTOCOLS[0]}\r\n\r\n"
            ).encode()
        )
        return s.recv(4096).decode()


def test_a_foreign_origin_is_refused_at_the_handshake(bridge: FoxgloveBridge) -> None:
    reason = refused(bridge.url, origin="http://evil.example.com")
    assert reason == (
        "origin http://evil.example.com is not allowed (only pages of this machine and "
        "https://app.foxglove.dev; see --allow-origin)\n"
    )
    assert "not allowed" in refused(bridge.url, origin="null")  # a sandboxed frame, a file
    assert "not allowed" in refused(bridge.url, origin="https://app.foxglove.dev.evil.com")
    # a DNS-rebound page names its own host
    port = bridge.port
    answer = raw_handshake(port, host=f"evil.com:{port}", origin="http://localhost:3000")
    assert answer.startswith("HTTP/1.1 403 Forbidden\r\n")
    assert answer.endswith(f"host 'evil.com:{port}' is not this machine\n")
    assert bridge.server.clients() == 0


@pytest.mark.parametrize(
    "origin",
    [None, FOXGLOVE_APP, "http://localhost:8080", "http://127.0.0.1:3000", "https://[::1]:9"],
)
def test_the_app_pages_of_this_machine_and_non_browsers_are_served(
    bridge: FoxgloveBridge, origin: str | None
) -> None:
    client = FoxgloveClient(bridge.url, origin=origin)
    try:
        assert client.server_info["name"] == "belvedere"
    finally:
        client.close()


def test_allowed_origins_are_served_and_bad_ones_refused(graph: Graph) -> None:
    bridge = FoxgloveBridge(graph, port=0, allow_origins=["https://studio.example.org"])
    try:
        FoxgloveClient(bridge.url, origin="https://studio.example.org").close()
        assert "see --allow-origin" in refused(bridge.url, origin="https://other.example.org")
    finally:
        bridge.close()
    with pytest.raises(FoxgloveBridgeError, match="origin 'ftp://x' is not scheme://host"):
        FoxgloveBridge(graph, port=0, allow_origins=["ftp://x"])


def test_beyond_this_machine_a_client_needs_the_token(graph: Graph) -> None:
    # another address makes a token (not bound here: tests stay on loopback) …
    assert ServerAccess("0.0.0.0").token is not None
    assert ServerAccess("192.0.2.7").token is not None
    assert ServerAccess("127.0.0.1").token is None
    # … and a bridge with one refuses a client without it, whatever its origin
    bridge = FoxgloveBridge(graph, port=0, token="s3cret")
    try:
        assert bridge.url == f"ws://127.0.0.1:{bridge.port}/?token=s3cret"
        plain = f"ws://127.0.0.1:{bridge.port}"
        reason = refused(plain, origin=None)
        assert reason.startswith("this Foxglove bridge needs its token")
        assert "needs its token" in refused(f"{plain}/?token=wrong", origin=FOXGLOVE_APP)
        FoxgloveClient(bridge.url).close()
    finally:
        bridge.close()


def test_the_cli_says_the_token_url_off_loopback(
    endpoint: str, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    # 127.0.0.2 is loopback too; make 127.0.0.1 count as "another address" to stay on it
    monkeypatch.setattr("belvedere.access.is_loopback", lambda host: host == "localhost")
    assert main(["foxglove", "--host", "127.0.0.1", "--port", "0", "--duration", "0.2"]) == 0
    err = capsys.readouterr().err
    assert "foxglove: serving beyond this machine on 127.0.0.1: clients need the token" in err
    assert "/?token=" in err
    assert main(["foxglove", "--allow-origin", "nope", "--duration", "0"]) == 2
    assert "origin 'nope' is not scheme://host[:port]" in capsys.readouterr().err


HOSTILE_TEXT = [
    "not json",
    "[]",
    "null",
    '{"op": 5}',
    '{"op": "bogus"}',
    '{"op": "subscribe"}',
    '{"op": "subscribe", "subscriptions": [{"id": -1, "channelId": 1}]}',
    '{"op": "subscribe", "subscriptions": [{"id": 1, "channelId": 99999}]}',
    '{"op": "subscribe", "subscriptions": [{"id": 1e30, "channelId": 1}]}',
    '{"op": "subscribe", "subscriptions": [{"id": ' + "9" * 4000 + ', "channelId": 1}]}',
    '{"op": "subscribe", "subscriptions": [' + "[" * 100_000 + "]" * 100_000 + "]}",
    '{"op": "unsubscribe", "subscriptionIds": [7, "x"]}',
    '{"op": "advertise", "channels": [{"id": 1, "topic": "", "encoding": "json", '
    '"schemaName": "std_msgs/String"}]}',
    '{"op": "advertise", "channels": [{"id": 2, "topic": "/a b", "encoding": "json", '
    '"schemaName": "std_msgs/String"}]}',
    '{"op": "advertise", "channels": [{"id": 3, "topic": "/x", "encoding": "cbor", '
    '"schemaName": "std_msgs/String"}]}',
    '{"op": "advertise", "channels": [{"id": 4, "topic": "/x", "encoding": "json", '
    '"schemaName": "no_such/Type"}]}',
    '{"op": "advertise", "channels": [{"id": 4294967296, "topic": "/x"}]}',
    '{"op": "unadvertise", "channelIds": [123456]}',
    '{"op": "getParameters", "parameterNames": [1, 2]}',
    '{"op": "setParameters", "parameters": [{"name": "", "value": 1}]}',
    '{"op": "setParameters", "parameters": [{"name": "/", "value": {}}]}',
    '{"op": "setParameters", "parameters": [{"name": "/x", "value": NaN, "type": "float64"}]}',
    '{"op": "setParameters", "parameters": [{"name": "/x", "value": 1e999, "type": "float64"}]}',
    '{"op": "setParameters", "parameters": [{"name": "/x", "value": "QQ==", '
    '"type": "byte_array"}]}',
    '{"op": "subscribeParameterUpdates", "parameterNames": {}}',
    '{"op": "fetchAsset", "uri": "file:///etc/passwd", "requestId": 1}',
    '{"op": "subscribeConnectionGraph"}',
]
HOSTILE_BINARY = [
    b"",
    b"\x01",
    b"\x01\x00\x00",
    struct.pack("<BI", 1, 4242) + b"data",  # a channel never advertised
    struct.pack("<BI", 1, 0xFFFFFFFF),
    b"\x02" + b"\x00" * 12,  # a service call
    b"\xff" * 64,
]


def test_malformed_client_messages_are_refused_to_that_client_alone(
    graph: Graph, bridge: FoxgloveBridge
) -> None:
    node = graph.create_node("talker")
    pub = node.publisher("/chatter", "std_msgs/String")
    node.timer(0.05, lambda: pub.publish_data({"data": "hi"}))
    received: list[str] = []
    graph.create_node("listener").subscribe(
        "/cmd", "std_msgs/String", lambda m: received.append(m.data)
    )
    graph.params.set("/x", 1)
    graph.start(rtf=1.0)
    attacker = FoxgloveClient(bridge.url)
    bystander = FoxgloveClient(bridge.url)
    try:
        sub = bystander.subscribe("/chatter")
        bystander.wait(lambda: bystander.received(sub), what="a message before the attack")
        for frame in HOSTILE_TEXT:
            attacker.ws.send(frame)
        for data in HOSTILE_BINARY:
            attacker.ws.send(data)
        expected = len(HOSTILE_TEXT) + len(HOSTILE_BINARY) - 1  # unadvertising nothing: quiet
        attacker.wait(lambda: len(attacker.statuses) >= expected, what="a status for each")
        texts = [s["message"] for s in attacker.statuses]
        assert all(s["level"] == 2 for s in attacker.statuses), texts
        assert "invalid message: Expecting value: line 1 column 1 (char 0)" in texts
        assert "invalid message: unknown op 'bogus'" in texts
        assert "invalid message: JSON nested too deep" in texts
        assert "Unknown channel ID: 99999" in texts
        assert "invalid message: id -1 is not an unsigned 32-bit integer" in texts
        assert "invalid message: 'id' must be an unsigned 32-bit integer, not 1e+30" in texts
        assert (
            "invalid message: id 999999999999…(4000 digits) is not an unsigned 32-bit integer"
            in texts
        )
        assert "invalid message: NaN is not a JSON number" in texts
        assert "cannot publish on '': empty graph name" in texts
        assert any(t.startswith("cannot publish on '/a b': graph name") for t in texts), texts
        assert "cannot publish on /x in 'cbor': use ros1 or json" in texts
        assert "cannot set '': graph name '' is not resolved (must start with '/')" in texts
        assert "cannot set '/': the whole parameter tree cannot be set from Foxglove" in texts
        assert "'fetchAsset' is not served by this bridge" in texts
        assert "unknown client channel id 4242: advertise it first" in texts
        assert "invalid message: unknown binary opcode 255" in texts
        assert "service calls are not served by this bridge" in texts
        assert not bystander.statuses
        assert graph.params.get("/x") == 1
        # the bridge and the graph go on: the bystander still receives, the attacker too
        count = len(bystander.received(sub))
        bystander.wait(lambda: len(bystander.received(sub)) > count + 2, what="more messages")
        cid = attacker.advertise("/cmd", "json", "std_msgs/String")
        attacker.publish(cid, b'{"data": "still here"}')
        wait_until(lambda: received == ["still here"], what="the attacker's valid message")
        assert graph.executor.thread is not None
        assert graph.executor.thread.is_alive()
    finally:
        attacker.close()
        bystander.close()


def test_a_client_that_does_not_read_is_disconnected_not_waited_for(
    graph: Graph, bridge: FoxgloveBridge, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Statuses are never dropped: a client that floods and never reads is cut off once its
    queue holds CONTROL_BACKLOG of them (small here; the client's receive buffer too)."""
    monkeypatch.setattr("belvedere.foxglove._server.CONTROL_BACKLOG", 64)
    graph.start(rtf=1.0)
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 2048)
    sock.settimeout(DEADLINE)
    sock.connect(("127.0.0.1", bridge.port))
    ws = connect(bridge.url, sock=sock, subprotocols=list(SUBPROTOCOLS), max_queue=1)
    flood = json.dumps({"op": "bogus" + "x" * 1000})

    def send_until_closed() -> None:
        for _ in range(200_000):
            ws.send(flood)
            if bridge.server.clients() == 0:
                ws.recv(timeout=DEADLINE)  # (raises ConnectionClosed once it reads that)

    try:
        with pytest.raises(websockets.exceptions.ConnectionClosed):
            send_until_closed()
    finally:
        ws.close()
    wait_until(lambda: bridge.server.clients() == 0, what="the flooding client to be dropped")
    FoxgloveClient(bridge.url).close()
