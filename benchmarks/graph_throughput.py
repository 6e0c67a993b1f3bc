"""Graph throughput and latency, with bare Zenoh + rosbags as the reference in the same run.

1. In-process: Twist messages published and delivered on one graph (target >= 500k msg/s).
2. Between processes, BLOCK congestion control: belvedere's graph vs bare Zenoh publishing
   rosbags-serialized Twists to a subscriber that deserializes them (target >= 0.7x, no loss).
3. Round-trip latency: publish a Twist, another process echoes it back (median, p99).

    python benchmarks/graph_throughput.py [--messages 200000]
"""

from __future__ import annotations

import argparse
import socket
import statistics
import subprocess
import sys
import time
from typing import Any

from belvedere.graph import Graph, ZenohTransport
from belvedere.msgs import message_from_data, types


def free_endpoint() -> str:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{s.getsockname()[1]}"


def in_process(n: int) -> float:
    g = Graph(sim_time=True)
    a, b = g.create_node("a"), g.create_node("b")
    count = [0]

    def on_msg(_: Any) -> None:
        count[0] += 1

    b.subscribe("/cmd_vel", "geometry_msgs/Twist", on_msg, queue_size=0)
    pub = a.publisher("/cmd_vel", "geometry_msgs/Twist")
    msg = message_from_data("geometry_msgs/Twist", {"linear": {"x": 0.2}})
    batch = 1000
    start = time.perf_counter()
    for _ in range(n // batch):
        for _ in range(batch):
            pub.publish(msg)
        g.spin_once()
    elapsed = time.perf_counter() - start
    assert count[0] == n // batch * batch
    return count[0] / elapsed


# The receiving processes: print the count and rate when they have N messages.
OURS_RX = """
import sys, time, threading
from belvedere.graph import Graph, ZenohTransport
n = int(sys.argv[2]); done = threading.Event(); t = []
g = Graph(sim_time=False, transport=ZenohTransport(endpoint=sys.argv[1], role="listen"))
def on(m):
    t.append(time.perf_counter())
    if len(t) == n: done.set()
g.create_node("rx").subscribe("/cmd_vel", "geometry_msgs/Twist", on, queue_size=0)
g.start(rtf=None); print("READY", flush=True)
ok = done.wait(120)
print(len(t), (len(t) - 1) / (t[-1] - t[0]) if len(t) > 1 else 0.0, flush=True)
g.shutdown()
"""

BARE_RX = """
import sys, time, threading, json, zenoh
from rosbags.typesys import Stores, get_typestore
ts = get_typestore(Stores.ROS1_NOETIC)
n = int(sys.argv[2]); done = threading.Event(); t = []
c = zenoh.Config()
c.insert_json5("mode", '"peer"'); c.insert_json5("scouting/multicast/enabled", "false")
c.insert_json5("scouting/gossip/enabled", "false")
c.insert_json5("listen/endpoints", json.dumps([sys.argv[1]]))
s = zenoh.open(c)
def on(sample):
    ts.deserialize_cdr(sample.payload.to_bytes(), "geometry_msgs/msg/Twist")
    t.append(time.perf_counter())
    if len(t) == n: done.set()
sub = s.declare_subscriber("bv/t/cmd_vel", on)
print("READY", flush=True)
done.wait(120)
print(len(t), (len(t) - 1) / (t[-1] - t[0]) if len(t) > 1 else 0.0, flush=True)
s.close()
"""

ECHO = """
import sys
from belvedere.graph import Graph, ZenohTransport
g = Graph(sim_time=False, transport=ZenohTransport(endpoint=sys.argv[1], role="listen"))
n = g.create_node("echo")
back = n.publisher("/pong", "geometry_msgs/Twist")
n.subscribe("/ping", "geometry_msgs/Twist", back.publish, queue_size=0)
g.start(rtf=None); print("READY", flush=True)
sys.stdin.read()
g.shutdown()
"""


def _spawn(code: str, *args: str) -> subprocess.Popen[str]:
    proc = subprocess.Popen(
        [sys.executable, "-c", code, *args],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout is not None
    line = proc.stdout.readline().strip()
    if line != "READY":
        msg = f"receiver failed to start: {line!r}"
        raise RuntimeError(msg)
    return proc


def _result(proc: subprocess.Popen[str]) -> tuple[int, float]:
    out, _ = proc.communicate(timeout=180)
    received, rate = out.split()
    return int(received), float(rate)


def between_processes_ours(n: int) -> tuple[int, float]:
    endpoint = free_endpoint()
    rx = _spawn(OURS_RX, endpoint, str(n))
    g = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, role="connect"))
    pub = g.create_node("tx").publisher("/cmd_vel", "geometry_msgs/Twist")
    while not pub.topic.remote:
        time.sleep(0.01)
    msg = message_from_data("geometry_msgs/Twist", {"linear": {"x": 0.2}})
    for _ in range(n):
        pub.publish(msg)
    result = _result(rx)
    g.shutdown()
    return result


def between_processes_bare(n: int) -> tuple[int, float]:
    import json

    import zenoh

    endpoint = free_endpoint()
    rx = _spawn(BARE_RX, endpoint, str(n))
    c = zenoh.Config()
    c.insert_json5("mode", '"client"')
    c.insert_json5("connect/endpoints", json.dumps([endpoint]))
    session = zenoh.open(c)
    block = zenoh.CongestionControl.BLOCK
    zpub = session.declare_publisher("bv/t/cmd_vel", congestion_control=block)
    while not zpub.matching_status.matching:  # type: ignore[attr-defined]
        time.sleep(0.01)
    msg = message_from_data("geometry_msgs/Twist", {"linear": {"x": 0.2}})
    store = types().store
    for _ in range(n):
        zpub.put(bytes(store.serialize_cdr(msg, "geometry_msgs/msg/Twist")))
    result = _result(rx)
    session.close()  # type: ignore[no-untyped-call]
    return result


def round_trip(samples: int) -> list[float]:
    endpoint = free_endpoint()
    echo = _spawn(ECHO, endpoint)
    g = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, role="connect"))
    node = g.create_node("pinger")
    arrived: list[float] = []
    node.subscribe(
        "/pong", "geometry_msgs/Twist", lambda m: arrived.append(time.perf_counter()), queue_size=0
    )
    ping = node.publisher("/ping", "geometry_msgs/Twist")
    g.start(rtf=None)
    while not ping.topic.remote:
        time.sleep(0.01)
    time.sleep(0.3)
    msg = message_from_data("geometry_msgs/Twist", {"linear": {"x": 1.0}})
    times = []
    for _ in range(samples):
        before = len(arrived)
        sent = time.perf_counter()
        ping.publish(msg)
        while len(arrived) == before:
            time.sleep(0)
        times.append(arrived[-1] - sent)
    g.shutdown()
    assert echo.stdin is not None
    echo.stdin.close()
    echo.wait(timeout=10)
    return times


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--messages", type=int, default=200_000)
    args = parser.parse_args()
    n = args.messages

    rate = in_process(max(n, 500_000))
    print(f"in-process Twist pub/sub: {rate / 1e3:8.0f}k msg/s (target >= 500k)")

    bare_n, bare_rate = between_processes_bare(n)
    ours_n, ours_rate = between_processes_ours(n)
    print(f"inter-process, BLOCK, {n} Twists:")
    print(f"  bare Zenoh + rosbags: {bare_rate / 1e3:7.1f}k msg/s, received {bare_n}/{n}")
    print(f"  belvedere graph:      {ours_rate / 1e3:7.1f}k msg/s, received {ours_n}/{n}")
    print(f"  ratio: {ours_rate / bare_rate:.2f}x (target >= 0.7x), lost: {n - ours_n}")

    times = round_trip(2000)
    times.sort()
    print(
        f"round trip (publish -> echo in another process -> back): median "
        f"{statistics.median(times) * 1e6:.0f} us, p99 {times[int(len(times) * 0.99)] * 1e6:.0f} us"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
