"""Fuzzing ROS 1 bags and MCAP files as ``bag info``, ``bag play``, ``bag reindex`` and
``slam`` read them: byte-level mutations of real files written by belvedere's writers
(bits flipped, length and offset fields lying, truncated, spans deleted, duplicated or
spliced from another file) give the bag's messages or belvedere's own error — within a time
and memory bound, and the file untouched by a repair."""

from __future__ import annotations

import contextlib
import struct
import tracemalloc
from functools import cache
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from belvedere.bags import BagFile, Decoder, create_writer, info_text, open_bag, reindex
from belvedere.bags._model import encode
from belvedere.errors import BelvedereError
from belvedere.msgs import message_from_data
from tests.fuzz._bytes import ByteEdit, byte_edits, byte_mutant
from tests.fuzz._mutate import fuzz_settings, run_bounded

MEMORY: int = 48 << 20
"""What reading one mutant (a few dozen KiB) may allocate at most: a bound far below what a
lie believed would take (a declared 4 GiB), far above what the file needs."""

SEEDS = (
    ("bag", "none"),
    ("bag", "lz4"),
    ("bag", "bz2"),
    ("mcap", "none"),
    ("mcap", "lz4"),
    ("mcap", "zstd"),
)


@cache
def seed(ext: str, compression: str) -> bytes:
    """A small bag: odometry, a latched string and a few scans, in three chunks."""
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"seed.{ext}"
        writer = create_writer(path, compression=compression)
        enc = writer.encoding
        name = writer.add_connection(
            "/map_name", "std_msgs/msg/String", callerid="/m", latching=True
        )
        odom = writer.add_connection(
            "/odom", "nav_msgs/msg/Odometry", callerid="/g", latching=False
        )
        scan = writer.add_connection(
            "/scan", "sensor_msgs/msg/LaserScan", callerid="/g", latching=False
        )
        writer.write(name, 5, encode(message_from_data("std_msgs/String", {"data": "x"}), enc))
        odometry = encode(message_from_data("nav_msgs/Odometry", {"child_frame_id": "b"}), enc)
        ranges = {"ranges": [1.0] * 16, "angle_increment": 0.1}
        laser = encode(message_from_data("sensor_msgs/LaserScan", ranges), enc)
        for i in range(30):
            writer.write(odom, (i + 1) * 10_000_000, odometry)
            if i % 10 == 9:
                writer.write(scan, (i + 1) * 10_000_000, laser)
                writer.flush()
        writer.close()
        return path.read_bytes()


# --- where the length and offset fields are --------------------------------------------------

_U32 = struct.Struct("<I")
_U64 = struct.Struct("<Q")
_ROS1_WIDTHS = {
    b"index_pos": 8,
    b"chunk_pos": 8,
    b"size": 4,
    b"conn": 4,
    b"count": 4,
    b"conn_count": 4,
    b"chunk_count": 4,
    b"ver": 4,
    b"time": 4,
    b"start_time": 4,
    b"end_time": 4,
}


@cache
def ros1_fields(data: bytes) -> tuple[tuple[int, int], ...]:
    """(offset, width) of a ROS 1 bag's length fields, and of the header fields that give
    sizes, offsets, counts and times — in the file and in its uncompressed chunks."""
    out: list[tuple[int, int]] = []

    def walk(pos: int, end: int, depth: int) -> None:
        while pos + 4 <= end:
            (hlen,) = _U32.unpack_from(data, pos)
            out.append((pos, 4))
            p, hend = pos + 4, pos + 4 + hlen
            if hend + 4 > end:
                return
            op, compression = b"", b""
            while p + 4 <= hend:
                (flen,) = _U32.unpack_from(data, p)
                out.append((p, 4))
                name, _, value = data[p + 4 : p + 4 + flen].partition(b"=")
                if name in _ROS1_WIDTHS:
                    out.append((p + 5 + len(name), _ROS1_WIDTHS[name]))
                op = value if name == b"op" else op
                compression = value if name == b"compression" else compression
                p += 4 + flen
            (dlen,) = _U32.unpack_from(data, hend)
            out.append((hend, 4))
            if op == b"\x05" and compression == b"none" and depth == 0:
                walk(hend + 4, min(end, hend + 4 + dlen), 1)
            elif op == b"\x04":  # index data: (time, offset) entries
                out.extend((q + 8, 4) for q in range(hend + 4, min(end, hend + 4 + dlen) - 11, 12))
            pos = hend + 4 + dlen

    walk(13, len(data), 0)
    return tuple(out)


@cache
def mcap_fields(data: bytes) -> tuple[tuple[int, int], ...]:
    """(offset, width) of an MCAP file's record lengths and the fields that give sizes,
    offsets and counts — in the file and in its uncompressed chunks."""
    out: list[tuple[int, int]] = []

    def walk(pos: int, end: int, depth: int) -> None:
        while pos + 9 <= end:
            op = data[pos]
            (length,) = _U64.unpack_from(data, pos + 1)
            out.append((pos + 1, 8))
            body = pos + 9
            stop = min(end, body + length)
            if op == 0x06 and body + 32 <= stop:  # chunk
                out.extend([(body + 16, 8), (body + 24, 4), (body + 28, 4)])
                (clen,) = _U32.unpack_from(data, body + 28)
                out.append((body + 32 + clen, 8))
                if clen == 0 and depth == 0:
                    walk(body + 40, stop, 1)
            elif op == 0x08 and body + 36 <= stop:  # chunk index
                out.extend([(body + 16, 8), (body + 24, 8), (body + 32, 4)])
            elif op == 0x0B and body + 46 <= stop:  # statistics
                out.extend([(body, 8), (body + 42, 4)])
            elif op == 0x02 and body + 16 <= stop:  # footer
                out.extend([(body, 8), (body + 8, 8)])
            elif op == 0x0E and body + 17 <= stop:  # summary offset
                out.extend([(body + 1, 8), (body + 9, 8)])
            elif op in (0x03, 0x04) and body + 8 <= stop:  # schema, channel: names' lengths
                out.append((body + (2 if op == 0x03 else 4), 4))
            elif op == 0x07 and body + 6 <= stop:  # message index: its entries' length
                out.append((body + 2, 4))
            pos = body + length

    walk(8, len(data) - 8, 0)
    return tuple(out)


# --- what users do with a bag ----------------------------------------------------------------


def _use(bag: BagFile) -> int:
    """What info (with --freq), play and slam do with a bag; returns the messages read."""
    info_text(bag, freq=True)
    decoder = Decoder()
    read = 0
    for m in bag.messages(start_ns=bag.start_ns + 1):
        read += 1
        if decoder.usable(m.connection):
            # The player skips (and counts) a message that does not decode.
            with contextlib.suppress(Exception):
                decoder.decode(m)
    return read


def _check(path: Path, mutant: bytes, out: Path) -> None:
    path.write_bytes(mutant)
    tracemalloc.start()
    try:
        with run_bounded(20):
            try:
                bag = open_bag(path)
            except BelvedereError:
                pass
            else:
                try:
                    _use(bag)
                finally:
                    bag.close()
            with contextlib.suppress(BelvedereError):
                reindex(path, output_dir=out, force=True)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < MEMORY, f"reading the mutant allocated {peak:,} bytes"
    assert path.read_bytes() == mutant  # a repair never touches the original


@pytest.fixture(scope="module")
def places(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    root = tmp_path_factory.mktemp("bags")
    (root / "out").mkdir()
    return root, root / "out"


@fuzz_settings(150)
@given(st.sampled_from([s for s in SEEDS if s[0] == "bag"]), byte_edits(max_edits=3))
def test_ros1_bag_mutants(
    places: tuple[Path, Path], which: tuple[str, str], edits: list[ByteEdit]
) -> None:
    data = seed(*which)
    donors = [seed(*s) for s in SEEDS if s[0] == "bag"]
    mutant = byte_mutant(data, edits, ros1_fields(data), donors)
    root, out = places
    _check(root / "mutant.bag", mutant, out)


@fuzz_settings(150)
@given(st.sampled_from([s for s in SEEDS if s[0] == "mcap"]), byte_edits(max_edits=3))
def test_mcap_mutants(
    places: tuple[Path, Path], which: tuple[str, str], edits: list[ByteEdit]
) -> None:
    data = seed(*which)
    donors = [seed(*s) for s in SEEDS if s[0] == "mcap"]
    mutant = byte_mutant(data, edits, mcap_fields(data), donors)
    root, out = places
    _check(root / "mutant.mcap", mutant, out)


def test_the_seeds_read_whole(places: tuple[Path, Path]) -> None:
    """The fuzzers start from good files: each reads all 34 messages, and its fields are
    found."""
    root, _ = places
    for ext, compression in SEEDS:
        path = root / f"seed.{ext}"
        data = seed(ext, compression)
        path.write_bytes(data)
        bag = open_bag(path)
        try:
            assert sum(1 for _ in bag.messages()) == 34
        finally:
            bag.close()
        fields = ros1_fields(data) if ext == "bag" else mcap_fields(data)
        assert len(fields) > 20
