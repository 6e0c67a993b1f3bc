"""TCPROS messages read in chunks: many in one read are split apart, one cut across reads
is joined, one larger than the buffer is read whole, and a connection that ends inside a
message or announces an impossible length is an error, not a hang. Messages written in
parts (a large field apart) arrive whole."""

from __future__ import annotations

import socket
import struct
import threading
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from belvedere.msgs import message_from_data, types
from belvedere.ros1wire._tcpros import MAX_MESSAGE, FrameReader, TcprosError, write_frames

T = TypeVar("T")


def _frames(messages: list[bytes]) -> bytes:
    return b"".join(struct.pack("<I", len(m)) + m for m in messages)


def _send_in_pieces(sock: socket.socket, data: bytes, cuts: list[int]) -> threading.Thread:
    """Write ``data`` cut at ``cuts`` (each piece its own send), then close."""

    def write() -> None:
        with sock:
            at = 0
            for cut in [*sorted(c % (len(data) + 1) for c in cuts), len(data)]:
                sock.sendall(data[at : max(at, cut)])
                at = max(at, cut)

    thread = threading.Thread(target=write, daemon=True)
    thread.start()
    return thread


def _read_all(
    reader: FrameReader,
    read: Callable[[memoryview], T] = bytes,  # type: ignore[assignment]
) -> Iterator[list[T]]:
    while True:
        try:
            yield reader.batch(read)
        except TcprosError:
            return


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    messages=st.lists(
        st.one_of(st.binary(max_size=40), st.binary(min_size=60, max_size=300)), max_size=30
    ),
    cuts=st.lists(st.integers(min_value=0, max_value=10_000), max_size=12),
    chunk=st.sampled_from([8, 64, 256, 1 << 16]),
)
def test_messages_come_out_as_sent_however_the_bytes_are_cut(
    messages: list[bytes], cuts: list[int], chunk: int
) -> None:
    ours, theirs = socket.socketpair()
    with ours:
        writer = _send_in_pieces(theirs, _frames(messages), cuts)
        got = [m for batch in _read_all(FrameReader(ours, chunk), bytes) for m in batch]
        writer.join()
    assert got == messages


def test_many_messages_in_one_read_are_one_batch() -> None:
    messages = [bytes([i]) * 1000 for i in range(50)]
    ours, theirs = socket.socketpair()
    with ours, theirs:
        theirs.sendall(_frames(messages))
        batch = FrameReader(ours, 1 << 16).batch(bytes)
    assert batch == messages


def test_a_message_cut_across_reads_waits_for_its_end() -> None:
    ours, theirs = socket.socketpair()
    data = _frames([b"first", b"second message"])
    with ours, theirs:
        reader = FrameReader(ours, 1 << 16)
        theirs.sendall(data[:15])  # the first whole, the second's length and two bytes
        assert reader.batch(bytes) == [b"first"]
        theirs.sendall(data[15:])
        assert reader.batch(bytes) == [b"second message"]


def test_a_message_larger_than_the_buffer_is_read_whole_between_small_ones() -> None:
    big = bytes(range(256)) * 4096  # 1 MB
    messages = [b"before", big, b"after", b""]
    ours, theirs = socket.socketpair()
    with ours:
        writer = _send_in_pieces(theirs, _frames(messages), [3, 17, 5000, 700_000])
        got = [m for batch in _read_all(FrameReader(ours, 1 << 12), bytes) for m in batch]
        writer.join()
    assert got == messages


@pytest.mark.parametrize("chunk", [64, 4096, 1 << 16])
def test_messages_read_from_the_reused_buffer_stay_as_they_were_sent(chunk: int) -> None:
    """Scans (their ranges numpy arrays, views of what they are read from) and strings,
    read straight from the reader's buffer by the bridge's reader of borrowed bytes, are
    unchanged after the buffer has been filled again and again."""
    registry = types()
    scans = [
        message_from_data(
            "sensor_msgs/LaserScan",
            {"header": {"seq": i, "frame_id": "laser"}, "ranges": [float(i)] * (i * 7)},
        )
        for i in range(40)
    ]
    texts = [registry.cls("std_msgs/String")(data=f"{i}|" + "é" * i) for i in range(40)]
    for sent in (scans, texts):
        name = sent[0].__msgtype__
        data = [bytes(registry.store.serialize_ros1(m, name)) for m in sent]
        ours, theirs = socket.socketpair()
        with ours:
            writer = _send_in_pieces(theirs, _frames(data), [5, 333, 1000, 2500])
            reader = FrameReader(ours, chunk)
            read = registry.ros1_reader(name, borrowed=True)
            got = [m for batch in _read_all(reader, read) for m in batch]
            writer.join()
        assert got == sent if name.endswith("String") else _same_scans(got, sent)


def _same_scans(got: list[Any], sent: list[Any]) -> bool:
    return len(got) == len(sent) and all(
        g.header == s.header and np.array_equal(g.ranges, s.ranges)
        for g, s in zip(got, sent, strict=True)
    )


def test_a_connection_closed_inside_a_message_is_an_error() -> None:
    ours, theirs = socket.socketpair()
    with ours:
        with theirs:
            theirs.sendall(_frames([b"whole"]) + struct.pack("<I", 100) + b"cut")
        reader = FrameReader(ours, 1 << 16)
        assert reader.batch(bytes) == [b"whole"]
        with pytest.raises(TcprosError, match="the connection closed"):
            reader.batch(bytes)


def test_an_impossible_length_is_an_error_not_a_gigabyte_allocation() -> None:
    ours, theirs = socket.socketpair()
    with ours, theirs:
        theirs.sendall(struct.pack("<I", MAX_MESSAGE + 1))
        with pytest.raises(TcprosError, match=r"a message of \d+ bytes \(more than"):
            FrameReader(ours, 1 << 16).batch(bytes)


def test_messages_written_in_parts_read_back_whole() -> None:
    """Small messages joined into one send, large ones' parts (a head and a numpy array's
    memory) sent by sendmsg, interleaved: read back, each is its parts joined."""
    pixels = np.arange(3 << 20, dtype=np.uint64).astype(np.uint8)  # 3 MB: partial sends
    frames: list[tuple[bytes | memoryview, ...]] = [
        (b"small",),
        (b"head", pixels.data),
        (b"a", b"b", b""),
        (b"",),
        (memoryview(b"x" * 70_000),),
        (b"last",),
    ]
    ours, theirs = socket.socketpair()
    theirs.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4096)
    with ours:

        def write() -> None:
            with theirs:
                write_frames(theirs, frames)

        writer = threading.Thread(target=write, daemon=True)
        writer.start()
        got = [m for batch in _read_all(FrameReader(ours, 1 << 16), bytes) for m in batch]
        writer.join()
    assert got == [b"".join(bytes(p) for p in parts) for parts in frames]
