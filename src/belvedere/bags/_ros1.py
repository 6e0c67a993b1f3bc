"""ROS 1 bags (format 2.0): the format, written and read here (repair:
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
from collections import defaultdict
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, Final

import lz4.frame
from rosbags.interfaces import ConnectionExtRosbag1
from rosbags.rosbag1 import Reader, ReaderError

from belvedere.bags._model import BagError, BagMessage, Connection, ros1_definition

__all__ = [
    "MAGIC",
    "ChunkStats",
    "Ros1Bag",
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


class Ros1BagWriter:
    """Writes a ROS 1 bag laid out byte for byte as ROS 1's rosbag lays it out (its header
    record padded to 4096 bytes, which ``rosbag reindex`` and rosbag's append rewrite in
    place), a chunk at least every :meth:`flush`."""

    encoding: Final = "ros1"

    def __init__(
        self, path: Path, *, compression: str = "none", chunk_size: int = CHUNK_SIZE
    ) -> None:
        self.path = path
        try:
            self._f: BinaryIO = path.open("wb")
        except OSError as err:
            msg = f"cannot write {path}: {err.strerror or err}"
            raise BagError(msg) from None
        self._f.write(MAGIC)
        self._write_bag_header(0, 0, 0)
        self._compression = compression
        self._compress: Callable[[bytes], bytes] = {"lz4": _roslz4, "bz2": _bz2}.get(
            compression, bytes
        )
        self._chunk_size = chunk_size
        self._connections: list[bytes] = []
        """Each connection's record."""
        self._chunk_infos: list[bytes] = []
        self._new_chunk()

    def _new_chunk(self) -> None:
        self._buf = bytearray()
        self._index: dict[int, list[tuple[int, int]]] = defaultdict(list)
        self._start = 2**64
        self._end = 0

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
        buf = self._buf
        self._index[connection].append((stamp_ns, len(buf)))
        buf += _record(
            {"op": bytes([OP_MSGDATA]), "conn": _U32.pack(connection), "time": _time(stamp_ns)},
            data,
        )
        self._start = min(self._start, stamp_ns)
        self._end = max(self._end, stamp_ns)
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

    @property
    def size(self) -> int:
        """Bytes so far, the open chunk's too."""
        return self._f.tell() + len(self._buf)

    def flush(self) -> None:
        """Write the open chunk (if it holds messages) and hand the file to the system."""
        self._write_chunk()
        self._f.flush()

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


# --- reading ---------------------------------------------------------------------------------


class Ros1Bag:
    """An indexed ROS 1 bag, open for reading."""

    format: Final = "bag"

    def __init__(self, path: Path) -> None:
        self.path = path
        self._reader = Reader(path)
        try:
            self._reader.open()
        except ReaderError as err:
            text = str(err.args[0]) if err.args else str(err)
            if "not indexed" in text:
                msg = f"{path} is unindexed (its recording did not end cleanly)"
                raise BagError(msg, hint=f"belvedere bag reindex {path}") from None
            msg = f"cannot read {path}: {text}"
            raise BagError(msg) from None
        except OSError as err:
            msg = f"cannot read {path}: {err.strerror or err}"
            raise BagError(msg) from None
        self.version = "2.0"
        self._conns: dict[int, Connection] = {}
        self.counts: dict[int, int] = {}
        for c in self._reader.connections:
            ext = c.ext
            assert isinstance(ext, ConnectionExtRosbag1)
            self._conns[c.id] = Connection(
                id=c.id,
                topic=c.topic,
                msgtype=c.msgtype,
                encoding="ros1",
                md5sum=c.digest,
                definition=c.msgdef.data,
                callerid=ext.callerid,
                latching=ext.latching == 1,
            )
            self.counts[c.id] = c.msgcount
        infos = self._reader.chunk_infos
        counted = [i for i in infos if i.connection_counts]
        self.start_ns = min((i.start_time for i in counted), default=0)
        self.end_ns = max((i.end_time - 1 for i in counted), default=0)  # rosbags adds 1

    @property
    def connections(self) -> list[Connection]:
        return list(self._conns.values())

    @property
    def size(self) -> int:
        return self.path.stat().st_size

    def chunks(self) -> list[ChunkStats]:
        """Each chunk's compression and sizes (from the chunk records' headers)."""
        stats = []
        with self.path.open("rb") as f:
            for info in self._reader.chunk_infos:
                f.seek(info.pos)
                fields, _ = _read_header(f)
                if fields is None:
                    break
                length = _read_u32(f)
                stats.append(
                    ChunkStats(
                        fields.get("compression", b"none").decode(),
                        length or 0,
                        _U32.unpack(fields.get("size", b"\0\0\0\0"))[0],
                    )
                )
        return stats

    def messages(
        self,
        connections: Iterable[Connection] | None = None,
        start_ns: int | None = None,
        stop_ns: int | None = None,
    ) -> Iterator[BagMessage]:
        wanted = None if connections is None else {c.id for c in connections if c.id in self._conns}
        chosen = [c for c in self._reader.connections if wanted is None or c.id in wanted]
        if not chosen:
            return
        conns = self._conns
        try:
            for c, stamp, data in self._reader.messages(chosen, start_ns, stop_ns):
                yield BagMessage(conns[c.id], stamp, data)
        except ReaderError as err:
            msg = f"cannot read {self.path}: {err}"
            raise BagError(msg) from None

    def close(self) -> None:
        if self._reader.bio is not None:
            self._reader.close()


# --- records ---------------------------------------------------------------------------------


def _read_u32(f: BinaryIO) -> int | None:
    raw = f.read(4)
    return _U32.unpack(raw)[0] if len(raw) == 4 else None


def _parse_fields(raw: bytes) -> dict[str, bytes] | None:
    fields: dict[str, bytes] = {}
    pos = 0
    while pos < len(raw):
        if pos + 4 > len(raw):
            return None
        (size,) = _U32.unpack_from(raw, pos)
        pos += 4
        if pos + size > len(raw):
            return None
        name, sep, value = raw[pos : pos + size].partition(b"=")
        if not sep:
            return None
        fields[name.decode(errors="replace")] = value
        pos += size
    return fields


def _read_header(f: BinaryIO) -> tuple[dict[str, bytes] | None, int]:
    """A record header's fields (None if cut short or malformed) and its byte length."""
    size = _read_u32(f)
    if size is None or size > 1 << 26:
        return None, 0
    raw = f.read(size)
    if len(raw) != size:
        return None, 0
    return _parse_fields(raw), size + 4


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


def _unpack_time(raw: bytes) -> int:
    sec, nsec = _TIME.unpack(raw)
    return int(sec) * 1_000_000_000 + int(nsec)


def _decompress(compression: bytes, data: bytes) -> bytes | None:
    try:
        if compression == b"none":
            return data
        if compression == b"bz2":
            return bz2.decompress(data)
        if compression == b"lz4":
            return bytes(lz4.frame.decompress(data))
    except (OSError, ValueError, RuntimeError):
        return None
    return None
