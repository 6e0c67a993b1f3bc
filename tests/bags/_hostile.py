"""Hostile bags for the tests, built record by record: chunks whose declared sizes, offsets
and contents lie, laid out as the formats lay out honest ones (ROS 1: a 4104-byte bag
header, so the first chunk starts at offset 4117; MCAP: the first record after the header
at offset 30)."""

from __future__ import annotations

import bz2
import struct
import zlib
from collections.abc import Sequence
from dataclasses import dataclass

U32 = struct.Struct("<I")
U64 = struct.Struct("<Q")

ROS1_MAGIC = b"#ROSBAG V2.0\n"
ROS1_FIRST_CHUNK = 13 + 4104
MCAP_MAGIC = b"\x89MCAP0\r\n"
MCAP_FIRST_RECORD = 30
"""After the magic and a header record with profile ``ros2`` and library ``x``."""

STRING_MD5 = b"992ce8a1687cec8c8bd883ec73ca41d1"
HELLO = b"\x05\x00\x00\x00hello"
"""A std_msgs/String, ROS 1 and CDR alike up to the CDR header."""
HELLO_CDR = b"\x00\x01\x00\x00" + HELLO


def zeros_bz2(size: int) -> bytes:
    """A bz2 bomb: ``size`` zero bytes in a few dozen."""
    return bz2.compress(b"\0" * size, 9)


def zeros_zstd(size: int) -> bytes:
    from backports import zstd

    return bytes(zstd.compress(b"\0" * size))


# --- ROS 1 -------------------------------------------------------------------------------


def fields(items: dict[str, bytes]) -> bytes:
    body = b"".join(U32.pack(len(k) + 1 + len(v)) + k.encode() + b"=" + v for k, v in items.items())
    return U32.pack(len(body)) + body


def record(items: dict[str, bytes], data: bytes) -> bytes:
    return fields(items) + U32.pack(len(data)) + data


def stamp(ns: int) -> bytes:
    return struct.pack("<II", ns // 1_000_000_000, ns % 1_000_000_000)


def connection(
    conn: int,
    topic: str,
    msgtype: bytes = b"std_msgs/String",
    md5: bytes = STRING_MD5,
    definition: bytes = b"string data\n",
) -> bytes:
    header = fields(
        {"topic": topic.encode(), "type": msgtype, "md5sum": md5, "message_definition": definition}
    )
    return record({"op": b"\x07", "conn": U32.pack(conn), "topic": topic.encode()}, header[4:])


def message(conn: int, ns: int, data: bytes = HELLO) -> bytes:
    return record({"op": b"\x02", "conn": U32.pack(conn), "time": stamp(ns)}, data)


@dataclass
class Chunk:
    """One chunk: its records (inflated), and what its record and chunk info declare."""

    records: bytes
    messages: list[tuple[int, int]]
    """(connection, time) of each message in ``records``, for the chunk info."""
    compression: str = "none"
    data: bytes | None = None
    """The chunk record's data as stored (default: ``records`` compressed)."""
    size: int | None = None
    """The uncompressed size it declares (default: ``len(records)``)."""
    data_length: int | None = None
    """The data length its record declares (default: the data's)."""
    pos: int | None = None
    """The chunk position its chunk info gives (default: where it is)."""


def ros1_bag(
    chunks: Sequence[Chunk], connections: Sequence[bytes], *, index_pos: int | None = None
) -> bytes:
    """An indexed ROS 1 bag of ``chunks`` and ``connections`` (connection records)."""
    body = bytearray(ROS1_MAGIC + b"\0" * 4104)
    infos = []
    for chunk in chunks:
        pos = len(body)
        data = chunk.data
        if data is None:
            data = bz2.compress(chunk.records) if chunk.compression == "bz2" else chunk.records
        size = len(chunk.records) if chunk.size is None else chunk.size
        head = fields(
            {"op": b"\x05", "compression": chunk.compression.encode(), "size": U32.pack(size)}
        )
        length = len(data) if chunk.data_length is None else chunk.data_length
        body += head + U32.pack(length) + data
        counts: dict[int, int] = {}
        for conn, _ in chunk.messages:
            counts[conn] = counts.get(conn, 0) + 1
        times = [t for _, t in chunk.messages] or [0]
        info = record(
            {
                "op": b"\x06",
                "ver": U32.pack(1),
                "chunk_pos": U64.pack(pos if chunk.pos is None else chunk.pos),
                "start_time": stamp(min(times)),
                "end_time": stamp(max(times)),
                "count": U32.pack(len(counts)),
            },
            b"".join(U32.pack(c) + U32.pack(n) for c, n in sorted(counts.items())),
        )
        infos.append(info)
    where = len(body)
    body += b"".join(connections) + b"".join(infos)
    head = fields(
        {
            "op": b"\x03",
            "index_pos": U64.pack(where if index_pos is None else index_pos),
            "conn_count": U32.pack(len(connections)),
            "chunk_count": U32.pack(len(chunks)),
        }
    )
    padding = 4104 - len(head) - 4
    body[13:4117] = head + U32.pack(padding) + b" " * padding
    return bytes(body)


def hello_chunk(
    times: Sequence[int] = (1_000_000_000,),
    *,
    compression: str = "none",
    data: bytes | None = None,
    size: int | None = None,
    data_length: int | None = None,
    pos: int | None = None,
) -> Chunk:
    """A chunk holding connection 0 (``/x``) and a message at each of ``times``."""
    records = connection(0, "/x") + b"".join(message(0, t) for t in times)
    return Chunk(records, [(0, t) for t in times], compression, data, size, data_length, pos)


# --- MCAP --------------------------------------------------------------------------------


def mrecord(op: int, body: bytes) -> bytes:
    return struct.pack("<BQ", op, len(body)) + body


def mstring(text: bytes) -> bytes:
    return U32.pack(len(text)) + text


def schema(sid: int = 1) -> bytes:
    return mrecord(
        0x03,
        struct.pack("<H", sid)
        + mstring(b"std_msgs/String")
        + mstring(b"ros2msg")
        + mstring(b"string data"),
    )


def channel(cid: int = 0, sid: int = 1, encoding: bytes = b"cdr", topic: bytes = b"/x") -> bytes:
    return mrecord(
        0x04,
        struct.pack("<HH", cid, sid) + mstring(topic) + mstring(encoding) + U32.pack(0),
    )


def mmessage(cid: int, ns: int, data: bytes = HELLO_CDR) -> bytes:
    return mrecord(0x05, struct.pack("<HIQQ", cid, 1, ns, ns) + data)


def mchunk(
    records: bytes,
    *,
    start: int = 1_000_000_000,
    end: int = 1_000_000_000,
    compression: bytes = b"",
    data: bytes | None = None,
    size: int | None = None,
    crc: int | None = None,
) -> bytes:
    """A chunk record holding ``records`` (or ``data`` as stored, declaring ``size``)."""
    stored = records if data is None else data
    declared = len(records) if size is None else size
    check = zlib.crc32(records) if crc is None else crc
    body = struct.pack("<QQQI", start, end, declared, check) + mstring(compression)
    return mrecord(0x06, body + U64.pack(len(stored)) + stored)


def mcap_file(
    records: Sequence[bytes],
    *,
    summary: bool = True,
    counts: dict[int, int] | None = None,
    chunk_pos: dict[int, int] | None = None,
    summary_start: int | None = None,
) -> bytes:
    """An MCAP file of ``records`` (its data section), with a summary (schemas and channels
    found at the top level, a chunk index per chunk record, statistics of ``counts``) unless
    ``summary`` is false. ``chunk_pos`` overrides the i-th chunk index's offset."""
    out = bytearray(MCAP_MAGIC + mrecord(0x01, mstring(b"ros2") + mstring(b"x")))
    assert len(out) == MCAP_FIRST_RECORD
    indexes: list[bytes] = []
    tops: list[bytes] = []
    for rec in records:
        pos = len(out)
        out += rec
        if rec[0] == 0x06:
            start, end, size = struct.unpack_from("<QQQ", rec, 9)
            (clen,) = U32.unpack_from(rec, 9 + 28)
            compression = rec[9 + 32 : 9 + 32 + clen]
            (compressed,) = U64.unpack_from(rec, 9 + 32 + clen)
            i = len(indexes)
            at = pos if chunk_pos is None or i not in chunk_pos else chunk_pos[i]
            indexes.append(
                mrecord(
                    0x08,
                    struct.pack("<QQQQ", start, end, at, len(rec))
                    + U32.pack(0)
                    + U64.pack(0)
                    + mstring(compression)
                    + U64.pack(compressed)
                    + U64.pack(size),
                )
            )
        elif rec[0] in (0x03, 0x04):
            tops.append(rec)
    out += mrecord(0x0F, U32.pack(0))
    start_of_summary = 0
    if summary:
        start_of_summary = len(out)
        out += b"".join(tops) + b"".join(indexes)
        items = b"".join(struct.pack("<HQ", c, n) for c, n in sorted((counts or {}).items()))
        stats = struct.pack("<QHIIIIQQ", sum((counts or {}).values()), 0, 0, 0, 0, 0, 0, 0)
        out += mrecord(0x0B, stats + U32.pack(len(items)) + items)
    if summary_start is not None:
        start_of_summary = summary_start
    out += mrecord(0x02, U64.pack(start_of_summary) + U64.pack(0) + U32.pack(0)) + MCAP_MAGIC
    return bytes(out)
