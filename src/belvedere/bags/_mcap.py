"""MCAP files (https://mcap.dev/spec): the format, and writing it (reading:
:mod:`belvedere.bags._mcap_read`; recovery: :mod:`belvedere.bags._mcap_recover`).

belvedere writes the ``ros2`` profile: each message CDR-encoded, exactly as belvedere's
transport carries it, under a ``ros2msg`` schema that describes that layout (belvedere's
types are ROS 1's, so a ``std_msgs/Header`` keeps its ``seq``); Foxglove and rosbags (with
its ROS 1 Noetic type store) read them. Latched topics are marked as rosbag2 marks them
(``offered_qos_profiles`` with transient-local durability). It reads that profile and the
``ros1`` one (ROS 1 wire format under ``ros1msg`` schemas, as ``mcap convert`` makes from a
ROS 1 bag).

Messages go in chunks, each followed by its message indexes; the summary at the end holds
the schemas, channels, chunk indexes and statistics. A chunk is written at least every
second, so a recording killed outright loses at most its last second: :func:`recover_mcap`
keeps every whole chunk and writes the summary again.
"""

from __future__ import annotations

import struct
import zlib
from collections import defaultdict
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, BinaryIO, Final

import lz4.frame

from belvedere import __version__
from belvedere.bags._chunked import ChunkWriter
from belvedere.bags._input import BagInput, Damaged, inflate_chunk
from belvedere.bags._model import BagError, cdr_schema

__all__ = ["MAGIC", "McapWriter"]

MAGIC: Final = b"\x89MCAP0\r\n"
CHUNK_SIZE: Final = 768 * 1024

OP_HEADER: Final = 0x01
OP_FOOTER: Final = 0x02
OP_SCHEMA: Final = 0x03
OP_CHANNEL: Final = 0x04
OP_MESSAGE: Final = 0x05
OP_CHUNK: Final = 0x06
OP_MESSAGE_INDEX: Final = 0x07
OP_CHUNK_INDEX: Final = 0x08
OP_STATISTICS: Final = 0x0B
OP_SUMMARY_OFFSET: Final = 0x0E
OP_DATA_END: Final = 0x0F

_U16: Final = struct.Struct("<H")
_U32: Final = struct.Struct("<I")
_U64: Final = struct.Struct("<Q")
_RECORD: Final = struct.Struct("<BQ")
_MESSAGE: Final = struct.Struct("<HIQQ")
_IDS: Final = struct.Struct("<HH")
_CHUNK: Final = struct.Struct("<QQQI")
_CHUNK_INDEX: Final = struct.Struct("<QQQ")
_SIZES: Final = struct.Struct("<QQ")
_COUNT: Final = struct.Struct("<HQ")

_QOS: Final = (
    "- history: 1\n  depth: {depth}\n  reliability: 1\n  durability: {durability}\n"
    "  deadline:\n    sec: 0\n    nsec: 0\n  lifespan:\n    sec: 0\n    nsec: 0\n"
    "  liveliness: 1\n  liveliness_lease_duration:\n    sec: 0\n    nsec: 0\n"
    "  avoid_ros_namespace_conventions: false"
)
"""rosbag2's offered_qos_profiles (its version 8 spelling): durability 1 is transient local
(ROS 2's latching), 2 volatile."""


def _string(text: str | bytes) -> bytes:
    raw = text.encode() if isinstance(text, str) else text
    return _U32.pack(len(raw)) + raw


def _map(items: dict[str, str]) -> bytes:
    body = b"".join(_string(k) + _string(v) for k, v in items.items())
    return _U32.pack(len(body)) + body


def _record(op: int, body: bytes) -> bytes:
    return _RECORD.pack(op, len(body)) + body


@dataclass(frozen=True, slots=True)
class _Schema:
    id: int
    name: str
    encoding: str
    data: bytes

    def record(self) -> bytes:
        return _record(
            OP_SCHEMA,
            _U16.pack(self.id) + _string(self.name) + _string(self.encoding) + _string(self.data),
        )


@dataclass(frozen=True, slots=True)
class _Channel:
    id: int
    schema_id: int
    topic: str
    encoding: str
    metadata: dict[str, str]

    def record(self) -> bytes:
        body = _U16.pack(self.id) + _U16.pack(self.schema_id) + _string(self.topic)
        return _record(OP_CHANNEL, body + _string(self.encoding) + _map(self.metadata))


@dataclass
class _Summary:
    """What the summary section lists; the writer and the recovery fill it alike."""

    schemas: dict[int, _Schema] = field(default_factory=dict)
    channels: dict[int, _Channel] = field(default_factory=dict)
    chunk_indexes: list[bytes] = field(default_factory=list)
    counts: dict[int, int] = field(default_factory=lambda: defaultdict(int))
    start: int = 2**64 - 1
    end: int = 0

    def add_message(self, channel: int, stamp: int) -> None:
        self.counts[channel] += 1
        self.start = min(self.start, stamp)
        self.end = max(self.end, stamp)

    def write(self, f: BinaryIO) -> None:
        """DataEnd, the summary, its offsets, the footer and the closing magic."""
        f.write(_record(OP_DATA_END, _U32.pack(0)))
        summary_start = f.tell()
        groups: list[tuple[int, int, int]] = []

        def group(op: int, records: Iterable[bytes]) -> None:
            start = f.tell()
            for rec in records:
                f.write(rec)
            if f.tell() > start:
                groups.append((op, start, f.tell() - start))

        group(OP_SCHEMA, (s.record() for s in self.schemas.values()))
        group(OP_CHANNEL, (c.record() for c in self.channels.values()))
        group(OP_CHUNK_INDEX, self.chunk_indexes)
        total = sum(self.counts.values())
        counts = b"".join(_U16.pack(c) + _U64.pack(n) for c, n in sorted(self.counts.items()))
        stats = struct.pack(
            "<QHIIIIQQ",
            total,
            len(self.schemas),
            len(self.channels),
            0,
            0,
            len(self.chunk_indexes),
            self.start if total else 0,
            self.end if total else 0,
        )
        group(OP_STATISTICS, [_record(OP_STATISTICS, stats + _U32.pack(len(counts)) + counts)])
        offsets_start = f.tell()
        for op, start, length in groups:
            f.write(_record(OP_SUMMARY_OFFSET, bytes([op]) + _U64.pack(start) + _U64.pack(length)))
        f.write(
            _record(OP_FOOTER, _U64.pack(summary_start) + _U64.pack(offsets_start) + _U32.pack(0))
        )
        f.write(MAGIC)


def _chunk_index(
    start: int,
    end: int,
    chunk_pos: int,
    chunk_len: int,
    index_offsets: dict[int, int],
    index_len: int,
    compression: str,
    compressed: int,
    uncompressed: int,
) -> bytes:
    offsets = b"".join(_U16.pack(c) + _U64.pack(o) for c, o in index_offsets.items())
    return _record(
        OP_CHUNK_INDEX,
        _U64.pack(start)
        + _U64.pack(end)
        + _U64.pack(chunk_pos)
        + _U64.pack(chunk_len)
        + _U32.pack(len(offsets))
        + offsets
        + _U64.pack(index_len)
        + _string(compression)
        + _U64.pack(compressed)
        + _U64.pack(uncompressed),
    )


def _message_indexes(
    f: BinaryIO, index: dict[int, list[tuple[int, int]]]
) -> tuple[dict[int, int], int]:
    """Write one message index per channel; returns (channel → offset, total length)."""
    start = f.tell()
    offsets = {}
    for channel, entries in sorted(index.items()):
        offsets[channel] = f.tell()
        body = b"".join(_U64.pack(t) + _U64.pack(o) for t, o in entries)
        f.write(_record(OP_MESSAGE_INDEX, _U16.pack(channel) + _U32.pack(len(body)) + body))
    return offsets, f.tell() - start


def _compressor(name: str) -> Callable[[bytes], bytes]:
    if name == "lz4":
        return lambda data: bytes(lz4.frame.compress(data))
    if name == "zstd":
        zstd = _zstd()
        return lambda data: bytes(zstd.compress(data))
    return lambda data: data


def _zstd() -> Any:
    try:
        from compression import zstd  # type: ignore[import-not-found]  # Python 3.14
    except ImportError:
        try:
            from backports import zstd
        except ImportError:
            msg = "zstd-compressed MCAP chunks need the backports.zstd package"
            raise BagError(msg) from None
    return zstd


# --- writing ---------------------------------------------------------------------------------


class McapWriter(ChunkWriter):
    """Writes an MCAP file (ros2 profile, CDR), a chunk at least every :meth:`flush`."""

    encoding: Final = "cdr"

    def __init__(
        self, path: Path, *, compression: str = "none", chunk_size: int = CHUNK_SIZE
    ) -> None:
        if compression == "bz2":
            msg = "MCAP has no bz2 compression: use --lz4 (or a .bag file)"
            raise BagError(msg)
        super().__init__(path, chunk_size)
        self._f.write(MAGIC)
        self._f.write(_record(OP_HEADER, _string("ros2") + _string(f"belvedere {__version__}")))
        self._compression = "" if compression == "none" else compression
        self._compress = _compressor(self._compression)
        self._summary = _Summary()
        self._schema_ids: dict[str, int] = {}
        self._seq: dict[int, int] = {}

    def add_connection(
        self, topic: str, msgtype: str, *, callerid: str | None, latching: bool
    ) -> int:
        summary = self._summary
        schema_id = self._schema_ids.get(msgtype)
        if schema_id is None:
            schema_id = self._schema_ids[msgtype] = len(summary.schemas) + 1
            schema = _Schema(schema_id, msgtype, "ros2msg", cdr_schema(msgtype).encode())
            summary.schemas[schema_id] = schema
            self._buf += schema.record()
        channel_id = len(summary.channels)
        metadata = {
            "offered_qos_profiles": _QOS.format(
                depth=1 if latching else 10, durability=1 if latching else 2
            )
        }
        if callerid:
            metadata["callerid"] = callerid
        channel = _Channel(channel_id, schema_id, topic, "cdr", metadata)
        summary.channels[channel_id] = channel
        self._buf += channel.record()
        self._seq[channel_id] = 0
        return channel_id

    def write(self, channel: int, stamp_ns: int, data: bytes) -> None:
        seq = self._seq[channel] + 1
        self._seq[channel] = seq
        self._indexed(channel, stamp_ns)
        buf = self._buf
        buf += _RECORD.pack(OP_MESSAGE, _MESSAGE.size + len(data))
        buf += _MESSAGE.pack(channel, seq & 0xFFFFFFFF, stamp_ns, stamp_ns)
        buf += data
        self._summary.add_message(channel, stamp_ns)
        if len(buf) >= self._chunk_size:
            self._write_chunk()

    def _write_chunk(self) -> None:
        if not self._index:
            return  # schemas and channels wait for their first message
        f = self._f
        raw = bytes(self._buf)
        data = self._compress(raw)
        start, end = self._start, self._end
        pos = f.tell()
        body = struct.pack("<QQQI", start, end, len(raw), zlib.crc32(raw))
        f.write(_record(OP_CHUNK, body + _string(self._compression) + _U64.pack(len(data)) + data))
        length = f.tell() - pos
        offsets, index_len = _message_indexes(f, self._index)
        self._summary.chunk_indexes.append(
            _chunk_index(
                start, end, pos, length, offsets, index_len, self._compression, len(data), len(raw)
            )
        )
        self._new_chunk()

    def close(self) -> None:
        self._write_chunk()
        if self._buf:  # connections that never had a message: keep them in the data section
            self._f.write(self._buf)
        self._summary.write(self._f)
        self._f.close()


# --- parsing (reading and recovery share it) ------------------------------------------------
# Each parser takes a record's body and ``base``, the body's offset in the file (or in its
# chunk's data), and raises Damaged at that offset plus the place of what is wrong.


@dataclass(frozen=True, slots=True)
class _ChunkRef:
    pos: int
    """Where the chunk record starts."""
    start: int
    end: int
    compression: str
    compressed: int
    uncompressed: int
    at: int = 0
    """Where the chunk-index record that names it is (0: found by reading the data)."""


_FIXED: Final = {
    OP_MESSAGE: 22,
    OP_CHUNK: 28,
    OP_CHUNK_INDEX: 36,
    OP_STATISTICS: 46,
}
"""Bytes of fixed fields each kind of record starts with."""


def _fixed(body: bytes, op: int, what: str, base: int) -> None:
    """Raise Damaged unless ``body`` holds the fixed fields of its kind of record."""
    need = _FIXED[op]
    if len(body) < need:
        text = f"{what} record of {len(body)} bytes, shorter than its {need} bytes of fixed fields"
        raise Damaged(base - 9, text)


def _read_bytes(buf: bytes, pos: int, what: str, base: int) -> tuple[bytes, int]:
    """A length-prefixed (uint32) field at ``buf[pos:]``, and where it ends."""
    end = len(buf)
    if pos + 4 > end:
        raise Damaged(base + pos, f"{what}: its length is cut short")
    (n,) = _U32.unpack_from(buf, pos)
    if pos + 4 + n > end:
        raise Damaged(base + pos, f"{what} of {n:,} bytes runs past its record")
    return buf[pos + 4 : pos + 4 + n], pos + 4 + n


def _read_string(buf: bytes, pos: int, what: str, base: int) -> tuple[str, int]:
    raw, end = _read_bytes(buf, pos, what, base)
    try:
        return raw.decode(), end
    except UnicodeDecodeError:
        raise Damaged(base + pos, f"{what} is not UTF-8 text") from None


def _read_map(buf: bytes, pos: int, what: str, base: int) -> tuple[dict[str, str], int]:
    raw, end = _read_bytes(buf, pos, what, base)
    base += pos + 4
    items = {}
    at = 0
    while at < len(raw):
        key, at = _read_string(raw, at, f"{what}: a key", base)
        value, at = _read_string(raw, at, f"{what}: a value", base)
        items[key] = value
    return items, end


def _u(buf: bytes, layout: struct.Struct, pos: int, what: str, base: int) -> tuple[Any, ...]:
    if pos + layout.size > len(buf):
        raise Damaged(base + pos, f"{what} is cut short")
    return layout.unpack_from(buf, pos)


def _parse_schema(body: bytes, base: int) -> _Schema:
    (sid,) = _u(body, _U16, 0, "schema record", base)
    name, pos = _read_string(body, 2, "schema name", base)
    encoding, pos = _read_string(body, pos, "schema encoding", base)
    data, _ = _read_bytes(body, pos, "schema data", base)
    return _Schema(sid, name, encoding, data)


def _parse_channel(body: bytes, base: int) -> _Channel:
    cid, sid = _u(body, _IDS, 0, "channel record", base)
    topic, pos = _read_string(body, 4, "channel topic", base)
    encoding, pos = _read_string(body, pos, "channel message encoding", base)
    metadata, _ = _read_map(body, pos, "channel metadata", base)
    return _Channel(cid, sid, topic, encoding, metadata)


def _parse_chunk_header(body: bytes, base: int) -> tuple[int, int, int, int, str, int, int]:
    """(start, end, uncompressed size, crc, compression, data offset, compressed size)."""
    _fixed(body, OP_CHUNK, "chunk", base)
    start, end, size, crc = _CHUNK.unpack_from(body, 0)
    compression, pos = _read_string(body, 28, "chunk compression", base)
    (compressed,) = _u(body, _U64, pos, "chunk data size", base)
    if pos + 8 + compressed != len(body):
        text = (
            f"chunk: {compressed:,} bytes of data declared where its record holds "
            f"{len(body) - pos - 8:,}"
        )
        raise Damaged(base + pos, text)
    return start, end, size, crc, compression, pos + 8, compressed


def _inflated_chunk(body: bytes, pos: int) -> tuple[_ChunkRef, bytes]:
    """The chunk record at ``pos`` whose ``body`` (all of it) was read: what it declares
    and its data, inflated and checked against its CRC.

    Raises:
        Damaged: at ``pos`` (the CRC, the compression) or at the header field that is wrong.
    """
    start, end, size, crc, compression, at, compressed = _parse_chunk_header(body, pos + 9)
    raw = inflate_chunk(compression, CODECS, body[at : at + compressed], size, pos)
    if crc and zlib.crc32(raw) != crc:
        raise Damaged(pos, "chunk: its data does not match its CRC")
    return _ChunkRef(pos, start, end, compression, compressed, size), raw


def _message_head(inp: BagInput, body: int, length: int) -> tuple[int, int]:
    """(channel id, log time) of the message record whose body, ``length`` bytes, is at
    file offset ``body`` (only its fixed fields are read).

    Raises:
        Damaged: the record is shorter than its fixed fields.
    """
    fixed = inp.read(body, min(length, _MESSAGE.size), "a message record")
    _fixed(fixed, OP_MESSAGE, "a message", body)
    cid, _, stamp, _ = _MESSAGE.unpack(fixed)
    return cid, stamp


def _parse_chunk_index(body: bytes, base: int) -> _ChunkRef:
    _fixed(body, OP_CHUNK_INDEX, "chunk index", base)
    start, end, pos = _CHUNK_INDEX.unpack_from(body, 0)
    _, at = _read_bytes(body, 32, "chunk index: message index offsets", base)
    at += 8  # the message indexes' length
    compression, at = _read_string(body, at, "chunk index: compression", base)
    compressed, uncompressed = _u(body, _SIZES, at, "chunk index: sizes", base)
    return _ChunkRef(pos, start, end, compression, compressed, uncompressed, base - 9)


def _parse_statistics(body: bytes, base: int) -> dict[int, int]:
    """Messages per channel id."""
    _fixed(body, OP_STATISTICS, "statistics", base)
    raw, _ = _read_bytes(body, 42, "statistics: channel message counts", base)
    if len(raw) % 10:
        raise Damaged(base + 42, f"statistics: {len(raw)} bytes of counts, not a multiple of 10")
    counts: dict[int, int] = {}
    for i in range(0, len(raw), 10):
        cid, count = _COUNT.unpack_from(raw, i)
        counts[cid] = count
    return counts


_INVALID: Final = "a record of kind 0x00, which the spec reserves as invalid"
"""(Zeros where records should be: a chunk bomb of zeros stops at its first record.)"""


def _records(buf: bytes, base: int) -> Iterator[tuple[int, int, int]]:
    """(op, body start, body end) of each record in ``buf``.

    Raises:
        Damaged: a record runs past the end of ``buf``, or is of kind 0x00.
    """
    end = len(buf)
    pos = 0
    while pos < end:
        if pos + 9 > end:
            raise Damaged(base + pos, "a record cut short")
        op, length = _RECORD.unpack_from(buf, pos)
        body = pos + 9
        if body + length > end:
            raise Damaged(base + pos, f"a record of {length:,} bytes runs past its section")
        if not op:
            raise Damaged(base + pos, _INVALID)
        yield op, body, body + length
        pos = body + length


def _msgtype(name: str) -> str:
    parts = [p for p in name.split("/") if p]
    return f"{parts[0]}/msg/{parts[1]}" if len(parts) == 2 else "/".join(parts)


CODECS: Final = {"": "", "lz4": "lz4", "zstd": "zstd"}
"""A chunk's compression → its codec for :func:`belvedere.bags._input.inflate_chunk`."""
