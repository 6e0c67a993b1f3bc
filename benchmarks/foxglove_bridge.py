"""A 360-beam LaserScan through the Foxglove bridge to a client, against the graph's own
throughput, same run.

The graph publishes the scan as fast as it can (simulated time, ``rtf=None``, a timer every
simulated millisecond). First a subscriber on the graph alone: the graph's messages per wall
second. Then the same with the Foxglove bridge and one WebSocket client subscribed to the
scan (``foxglove.sdk.v1``, binary messageData frames counted as they arrive): what the graph
publishes per second with the bridge attached, what reaches the client per second, and what
was dropped on the way (the bridge keeps the newest when the client is behind, as a ROS
subscriber with a full queue does).

    python benchmarks/foxglove_bridge.py [--messages 5000]

(Not foxglove.py: a script of that name would be imported as the SDK.)
"""

from __future__ import annotations

import argparse
import json
import threading
import time

import numpy as np
from websockets.sync.client import connect
from websockets.typing import Subprotocol

from belvedere.foxglove import FoxgloveBridge
from belvedere.graph import Graph

BEAMS = 360
PERIOD_S = 0.001


def _graph() -> tuple[Graph, list[int]]:
    graph = Graph(sim_time=True, clock_hz=None)
    node = graph.create_node("laser")
    pub = node.publisher("/scan", "sensor_msgs/LaserScan", queue_size=100)
    ranges = np.linspace(0.5, 8.0, BEAMS, dtype=np.float32).tolist()
    scan = pub.publish_data({"header": {"frame_id": "laser"}, "ranges": ranges})
    node.timer(PERIOD_S, lambda: pub.publish(scan))
    received = [0]

    def count(_: object) -> None:
        received[0] += 1

    graph.create_node("listener").subscribe("/scan", "sensor_msgs/LaserScan", count, queue_size=0)
    return graph, received


class Client(threading.Thread):
    """Subscribes to /scan and counts the messages that arrive."""

    def __init__(self, url: str) -> None:
        super().__init__(daemon=True)
        self.ws = connect(url, subprotocols=[Subprotocol("foxglove.sdk.v1")], proxy=None)
        self.count = 0
        """messageData frames logged after ``since_ns`` (graph time)."""
        self.since_ns = -1
        self.last = 0.0
        self.subscribed = threading.Event()
        self.stop = threading.Event()

    def run(self) -> None:
        channel = None
        while not self.stop.is_set():
            try:
                frame = self.ws.recv(timeout=0.2)
            except TimeoutError:
                continue
            if isinstance(frame, bytes):
                if frame[0] == 1:
                    self.subscribed.set()
                    if int.from_bytes(frame[5:13], "little") > self.since_ns:
                        self.count += 1
                        self.last = time.perf_counter()
                continue
            doc = json.loads(frame)
            if doc["op"] == "advertise" and channel is None:
                found = [c["id"] for c in doc["channels"] if c["topic"] == "/scan"]
                if found:
                    channel = found[0]
                    sub = {"id": 1, "channelId": channel}
                    self.ws.send(json.dumps({"op": "subscribe", "subscriptions": [sub]}))
        self.ws.close()


def alone(messages: int) -> float:
    graph, received = _graph()
    start = time.perf_counter()
    graph.run(duration=messages * PERIOD_S, rtf=None)
    wall = time.perf_counter() - start
    graph.shutdown()
    return received[0] / wall


def bridged(messages: int) -> tuple[float, float, int, int]:
    graph, received = _graph()
    bridge = FoxgloveBridge(graph, port=0)
    client = Client(bridge.url)
    client.start()
    while not client.subscribed.is_set():  # until messages flow (not timed)
        graph.run(duration=0.01, rtf=None)
    before_graph = received[0]
    client.since_ns = graph.now_ns()
    client.count = 0
    start = time.perf_counter()
    graph.run(duration=messages * PERIOD_S, rtf=None)
    graph_wall = time.perf_counter() - start
    published = received[0] - before_graph
    settle = time.perf_counter()
    while time.perf_counter() - max(client.last, settle) < 1.0:  # until nothing more comes
        time.sleep(0.05)
    got = client.count
    client.stop.set()
    client.join()
    bridge.close()
    graph.shutdown()
    return published / graph_wall, got / (client.last - start), got, published


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--messages", type=int, default=5000)
    args = parser.parse_args()
    graph_rate = alone(args.messages)
    with_bridge, to_client, got, published = bridged(args.messages)
    print(f"360-beam LaserScan, {args.messages} published as fast as the graph can")
    print(f"graph alone:               {graph_rate:9.0f} msg/s")
    print(f"graph with the bridge:     {with_bridge:9.0f} msg/s")
    print(
        f"through the bridge:        {to_client:9.0f} msg/s to the client "
        f"({got} of {published}, {100 * (1 - got / published):.1f} % dropped)"
    )
    print(f"ratio (client / graph alone): {to_client / graph_rate:.2f}")


if __name__ == "__main__":
    main()
