"""ROS 1 bags (format 2.0): the format, its records (every length checked as they are
parsed), and writing it (reading: :mod:`belvedere.bags._ros1_read`; repair:
:mod:`belvedere.bags._ros1_repair`).

The format (ROS wiki, Bags/Format/2.0): ``#ROSBAG V2.0\\n``, a bag header record padded to
4 KiB (where the index starts, how many connections and chunks), then chunks — each a chunk
record holding connection and message records, followed by one index-data record per
connection in it — and at the end the index: every connection record again and one
chunk-info record per chunk. A record is a header (``name=value`` fields, ``op`` its kind)
and data, each preceded by its length (little-endian uint32).

The writer lays the file out exactly as ROS 1's rosbag does — its bag header record is 4104
bytes, which ``rosbag reindex`` and rosbag's append mode rewrite in place (rosbags' writer
makes it 4096, which they then corrupt), and its LZ4 chunks are frames roslz4 can read — and
writes a chunk at least every second, so a recording killed outright loses at most its last
second; :func:`reindex_ros1` rebuilds the index of such a bag from its chunks.
"""

from __future__ import annotations

import bz2
import struct
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Final

import lz4.frame

from belvedere.bags._chunked import ChunkWriter
from belvedere.bags._input import BagInput, Damaged
from belvedere.bags._model import ros1_definition

__all__ = [
    "MAGIC",
    "ChunkStats",
    "Ros1BagWriter",
]

MAGIC: Final = b"#ROSBAG V2.0\n"
CHUNK_SIZE: Final = 768 * 1024
"""rosbag's default chunk size (``--chunksize``, 768 KiB)."""
HEADER_SIZE: Final = 4096
"""rosbag pads the bag header's fields to this many bytes."""

OP_MSGDATA: Final = 0x02
OP_BAGHEADER: Final = 0x03
OP_IDXDATA: Final = 0x04
OP_CHUNK: Final = 0x05
OP_CHUNK_INFO: Final = 0x06
OP_CONNECTION: Final = 0x07

_U32: Final = struct.Struct("<I")
_U64: Final = struct.Struct("<Q")
_TIME: Final = struct.Struct("<II")


@dataclass(frozen=True, slots=True)
class ChunkStats:
    compression: str
    compressed: int
    uncompressed: int


def _roslz4(data: bytes) -> bytes:
    """An LZ4 frame as ROS 1's roslz4 writes (and, unlike other frames, reads) it:
    independent 1 MiB blocks and a content checksum."""
    return bytes(
        lz4.frame.compress(
            data,
            block_size=lz4.frame.BLOCKSIZE_MAX1MB,
            block_linked=False,
            content_checksum=True,
            store_size=False,
        )
    )


def _bz2(data: bytes) -> bytes:
    return bz2.compress(data, 9)


# --- writing ---------------------------------------------------------------------------------


class Ros1BagWriter(ChunkWriter):
    """Writes a ROS 1 bag laid out byte for byte as ROS 1's rosbag lays it out (its header
    record padded to 4096 bytes, which ``rosbag reindex`` and rosbag's append rewrite in
    place), a chunk at least every :meth:`flush`."""

    encoding: Final = "ros1"

    def __init__(
        self, path: Path, *, compression: str = "none", chunk_size: int = CHUNK_SIZE
    ) -> None:
        super().__init__(path, chunk_size)
        self._f.write(MAGIC)
        self._write_bag_header(0, 0, 0)
        self._compression = compression
        self._compress: Callable[[bytes], bytes] = {"lz4": _roslz4, "bz2": _bz2}.get(
            compression, bytes
        )
        self._connections: list[bytes] = []
        """Each connection's record."""
        self._chunk_infos: list[bytes] = []

    def _write_bag_header(self, index_pos: int, conns: int, chunks: int) -> None:
        fields = _fields(
            {
                "op": bytes([OP_BAGHEADER]),
                "index_pos": _U64.pack(index_pos),
                "conn_count": _U32.pack(conns),
                "chunk_count": _U32.pack(chunks),
            }
        )
        padding = HEADER_SIZE - (len(fields) - 4)
        self._f.write(fields + _U32.pack(padding) + b" " * padding)

    def add_connection(
        self, topic: str, msgtype: str, *, callerid: str | None, latching: bool
    ) -> int:
        ros1_type, md5sum, text = ros1_definition(msgtype)
        conn = len(self._connections)
        header = {} if callerid is None else {"callerid": callerid.encode()}
        header |= {
            "latching": b"1" if latching else b"0",
            "md5sum": md5sum.encode(),
            "message_definition": text.encode(),
            "topic": topic.encode(),
            "type": ros1_type.encode(),
        }
        record = _record(
            {"op": bytes([OP_CONNECTION]), "conn": _U32.pack(conn), "topic": topic.encode()},
            _fields(header)[4:],
        )
        self._connections.append(record)
        self._buf += record
        return conn

    def write(self, connection: int, stamp_ns: int, data: bytes) -> None:
        self._indexed(connection, stamp_ns)
        buf = self._buf
        buf += _record(
            {"op": bytes([OP_MSGDATA]), "conn": _U32.pack(connection), "time": _time(stamp_ns)},
            data,
        )
        if len(buf) > self._chunk_size:
            self._write_chunk()

    def _write_chunk(self) -> None:
        if not self._index:
            return  # connection records wait for their first message
        f = self._f
        pos = f.tell()
        raw = bytes(self._buf)
        f.write(
            _record(
                {
                    "op": bytes([OP_CHUNK]),
                    "compression": self._compression.encode(),
                    "size": _U32.pack(len(raw)),
                },
                self._compress(raw),
            )
        )
        for conn, entries in sorted(self._index.items()):
            f.write(_index_record(conn, entries))
        self._chunk_infos.append(_chunk_info(pos, self._start, self._end, self._index))
        self._new_chunk()

    def close(self) -> None:
        f = self._f
        self._write_chunk()
        index_pos = f.tell()
        for record in self._connections:
            f.write(record)
        for record in self._chunk_infos:
            f.write(record)
        f.seek(len(MAGIC))
        self._write_bag_header(index_pos, len(self._connections), len(self._chunk_infos))
        f.close()


def _index_record(conn: int, entries: list[tuple[int, int]]) -> bytes:
    return _record(
        {
            "op": bytes([OP_IDXDATA]),
            "ver": _U32.pack(1),
            "conn": _U32.pack(conn),
            "count": _U32.pack(len(entries)),
        },
        b"".join(_time(t) + _U32.pack(o) for t, o in entries),
    )


def _chunk_info(pos: int, start: int, end: int, index: dict[int, list[tuple[int, int]]]) -> bytes:
    return _record(
        {
            "op": bytes([OP_CHUNK_INFO]),
            "ver": _U32.pack(1),
            "chunk_pos": _U64.pack(pos),
            "start_time": _time(start if index else 0),
            "end_time": _time(end if index else 0),
            "count": _U32.pack(len(index)),
        },
        b"".join(_U32.pack(c) + _U32.pack(len(e)) for c, e in sorted(index.items())),
    )


# --- records ---------------------------------------------------------------------------------


def _fields(items: dict[str, bytes]) -> bytes:
    parts = []
    for name, value in items.items():
        entry = name.encode() + b"=" + value
        parts.append(_U32.pack(len(entry)) + entry)
    body = b"".join(parts)
    return _U32.pack(len(body)) + body


def _record(items: dict[str, bytes], data: bytes) -> bytes:
    return _fields(items) + _U32.pack(len(data)) + data


def _time(ns: int) -> bytes:
    return _TIME.pack(ns // 1_000_000_000, ns % 1_000_000_000)


def parse_fields(buf: bytes, start: int, end: int, base: int = 0) -> dict[str, bytes]:
    """The ``name=value`` fields of a record header, ``buf[start:end]``.

    Raises:
        Damaged: a field runs past the header or has no ``=`` (at its offset + ``base``).
    """
    fields: dict[str, bytes] = {}
    pos = start
    while pos < end:
        if pos + 4 > end:
            raise Damaged(base + pos, "record header: a field's length is cut short")
        (size,) = _U32.unpack_from(buf, pos)
        pos += 4
        if pos + size > end:
            text = f"record header: a field of {size:,} bytes runs past the header"
            raise Damaged(base + pos - 4, text)
        name, sep, value = buf[pos : pos + size].partition(b"=")
        if not sep:
            raise Damaged(base + pos - 4, "record header: a field without '='")
        fields[name.decode(errors="replace")] = value
        pos += size
    return fields


def record_at(buf: bytes, pos: int, base: int = 0) -> tuple[dict[str, bytes], int, int]:
    """(header fields, data start, data end) of the record at ``buf[pos:]``.

    Raises:
        Damaged: its header or data runs past the end of ``buf``.
    """
    end = len(buf)
    if pos + 4 > end:
        raise Damaged(base + pos, "a record cut short")
    (hlen,) = _U32.unpack_from(buf, pos)
    hend = pos + 4 + hlen
    if hend + 4 > end:
        raise Damaged(base + pos, f"a record header of {hlen:,} bytes runs past the end")
    fields = parse_fields(buf, pos + 4, hend, base)
    (dlen,) = _U32.unpack_from(buf, hend)
    if hend + 4 + dlen > end:
        raise Damaged(base + pos, f"a record's data of {dlen:,} bytes runs past the end")
    return fields, hend + 4, hend + 4 + dlen


def read_record_header(
    inp: BagInput, pos: int, end: int | None = None
) -> tuple[dict[str, bytes], int, int]:
    """(header fields, data offset, data length) of the record at ``pos`` in the file (its
    data not read, only checked to lie before ``end`` or the end of the file).

    Raises:
        Damaged: at the file offset of what is wrong.
    """
    (hlen,) = _U32.unpack(inp.read(pos, 4, "a record's header length", end=end))
    header = inp.read(pos + 4, hlen, "a record header", end=end)
    fields = parse_fields(header, 0, hlen, pos + 4)
    at = pos + 4 + hlen
    (dlen,) = _U32.unpack(inp.read(at, 4, "a record's data length", end=end))
    inp.check(at + 4, dlen, "a record's data", end=end)
    return fields, at + 4, dlen


def field(fields: dict[str, bytes], name: str, size: int, at: int) -> bytes:
    """The value of field ``name``, which must be ``size`` bytes (0: any).

    This and the getters below raise Damaged (at ``at``, the record's offset) when the
    field is missing or not of its kind."""
    value = fields.get(name)
    if value is None:
        raise Damaged(at, f"record header: no field '{name}'")
    if size and len(value) != size:
        text = f"record header: field '{name}' is {len(value)} bytes, not {size}"
        raise Damaged(at, text)
    return value


def u32_field(fields: dict[str, bytes], name: str, at: int) -> int:
    """A uint32 field."""
    return int(_U32.unpack(field(fields, name, 4, at))[0])


def u64_field(fields: dict[str, bytes], name: str, at: int) -> int:
    """A uint64 field (an offset)."""
    return int(_U64.unpack(field(fields, name, 8, at))[0])


def time_field(fields: dict[str, bytes], name: str, at: int) -> int:
    """A time field (seconds and nanoseconds), in nanoseconds."""
    sec, nsec = _TIME.unpack(field(fields, name, 8, at))
    return int(sec) * 1_000_000_000 + int(nsec)


def text_field(fields: dict[str, bytes], name: str, at: int) -> str:
    """A UTF-8 text field."""
    try:
        return field(fields, name, 0, at).decode()
    except UnicodeDecodeError:
        raise Damaged(at, f"record header: field '{name}' is not UTF-8 text") from None


def op_of(fields: dict[str, bytes], at: int) -> int:
    """The record's kind (its ``op`` field)."""
    return field(fields, "op", 1, at)[0]


CODECS: Final = {"none": "", "bz2": "bz2", "lz4": "lz4"}
"""A chunk's compression → its codec for :func:`belvedere.bags._input.inflate_chunk`."""
