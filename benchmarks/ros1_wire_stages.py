"""Where a message's time goes between ROS 1 and belvedere, stage by stage, each against the
plain way of doing the same in the same run.

- read: 1 KB ``std_msgs/String`` messages written to a socket by another process as fast as
  it can, read, split and deserialized by the bridge's reader (:class:`FrameReader` and
  ``ros1_reader``), against a buffered file over the socket read 4 bytes then the message's,
  each message given to rosbags' ``deserialize_ros1``; CPU µs of the reading thread a message;
- graph: those messages published on the graph to a subscriber that reads each one's send
  time from its text (the benchmark ``ros1_wire.py``'s subscriber), executor CPU µs a
  message, against the same subscriber called in a bare loop;
- serialize: a 1 MB ``std_msgs/String`` and a 640 x 480 rgb8 ``Image`` to ROS 1 bytes as the
  bridge sends them (``ros1_parts``), against rosbags' ``serialize_ros1``.

    python benchmarks/ros1_wire_stages.py
"""

from __future__ import annotations

import socket
import struct
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np

from belvedere.graph import Graph
from belvedere.msgs import build, types
from belvedere.ros1wire._tcpros import FrameReader, TcprosError

COUNT = 300_000
STRING = "std_msgs/msg/String"
WRITER = """
import socket, struct, sys
raw = bytes.fromhex(sys.argv[2])
frames = (struct.pack("<I", len(raw)) + raw) * 50
with socket.create_connection(("127.0.0.1", int(sys.argv[1]))) as s:
    for _ in range(int(sys.argv[3]) // 50):
        s.sendall(frames)
"""


def _one_kb() -> bytes:
    msg = types().cls(STRING)(data=f"{time.time():.6f}|" + "x" * 1024)
    return bytes(types().store.serialize_ros1(msg, STRING))


def _reading(consume: Callable[[socket.socket], int]) -> float:
    """CPU µs a message of ``consume`` reading COUNT messages from another process."""
    with socket.create_server(("127.0.0.1", 0)) as server:
        port = server.getsockname()[1]
        writer = subprocess.Popen(
            [sys.executable, "-c", WRITER, str(port), _one_kb().hex(), str(COUNT)]
        )
        sock, _ = server.accept()
        with sock:
            start = time.thread_time()
            count = consume(sock)
            cpu = time.thread_time() - start
        writer.wait()
    assert count == COUNT, count
    return cpu / count * 1e6


def _plain_read(sock: socket.socket) -> int:
    deserialize, count = types().store.deserialize_ros1, 0
    with sock.makefile("rb", buffering=1 << 16) as reader:
        while len(head := reader.read(4)) == 4:
            deserialize(reader.read(struct.unpack("<I", head)[0]), STRING)
            count += 1
    return count


def _bridge_read(sock: socket.socket) -> int:
    reader, count = FrameReader(sock), 0
    message = types().ros1_reader(STRING, borrowed=True)
    try:
        while True:
            count += len(reader.batch(message))
    except TcprosError:
        return count


def _graph_delivery(msgs: list[Any]) -> tuple[float, float]:
    """Executor CPU µs a message published to the subscriber, and the subscriber alone."""
    got: list[tuple[float, float]] = []

    def take(msg: Any) -> None:
        got.append((time.time(), float(msg.data[: msg.data.index("|")])))

    start = time.thread_time()
    for msg in msgs:
        take(msg)
    bare = (time.thread_time() - start) / len(msgs) * 1e6
    got.clear()
    graph = Graph(sim_time=False, transport=None, clock_hz=None)
    graph.start(rtf=None)
    try:
        graph.create_node("sub").subscribe("/flood", STRING, take, queue_size=1000)
        pub = graph.create_node("pub").publisher("/flood", STRING, queue_size=1000)
        cpu: list[float] = []
        done = threading.Event()

        def batch(part: list[Any]) -> None:
            for msg in part:
                pub.publish(msg)

        def end() -> None:
            cpu.append(time.thread_time())
            done.set()

        graph.executor.post(lambda: cpu.append(time.thread_time()))
        for at in range(0, len(msgs), 60):  # the bridge's batches: a 64 KB read
            graph.executor.post(partial(batch, msgs[at : at + 60]))
        graph.executor.post(end)
        done.wait(60)
        assert len(got) == len(msgs), len(got)
        return (cpu[1] - cpu[0]) / len(msgs) * 1e6, bare
    finally:
        graph.shutdown()


def _per_call(fn: Callable[[], object], count: int) -> float:
    start = time.process_time()
    for _ in range(count):
        fn()
    return (time.process_time() - start) / count * 1e6


def main() -> None:
    plain, ours = _reading(_plain_read), _reading(_bridge_read)
    print(
        f"read, split, deserialize 1 KB: bridge {ours:.2f} µs a message, buffered file + "
        f"rosbags {plain:.2f} µs ({ours / plain:.2f}x)"
    )
    raw = _one_kb()
    msgs = [types().store.deserialize_ros1(raw, STRING) for _ in range(COUNT // 3)]
    delivered, bare = _graph_delivery(msgs)
    print(
        f"graph publish + delivery + subscriber: {delivered:.2f} µs a message, the "
        f"subscriber alone {bare:.2f} µs (the graph's share {delivered - bare:.2f} µs)"
    )
    registry = types()
    text = registry.cls(STRING)(data=f"{time.time():.6f}|" + "x" * (1 << 20))
    pixels = np.random.default_rng(0).integers(0, 255, 480 * 640 * 3, dtype=np.uint8)
    image = registry.cls("sensor_msgs/Image")(
        build.header(1, "camera"), 480, 640, "rgb8", 0, 1920, pixels
    )
    for label, msg in (("1 MB String", text), ("640x480 rgb8 Image", image)):
        name = msg.__msgtype__
        theirs = _per_call(partial(registry.store.serialize_ros1, msg, name), 200)
        parts = _per_call(partial(registry.ros1_parts, msg, name), 200)
        print(
            f"serialize {label}: bridge's parts {parts:.1f} µs, rosbags {theirs:.1f} µs "
            f"({parts / theirs:.2f}x)"
        )


if __name__ == "__main__":
    main()
