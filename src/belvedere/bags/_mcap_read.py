"""Reading MCAP files (see :mod:`belvedere.bags._mcap`): from their summary, or by reading
the data section when they have none."""

from __future__ import annotations

import heapq
import struct
from collections import defaultdict
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, Final

from belvedere.bags._mcap import (
    _MESSAGE,
    _U16,
    _U32,
    _U64,
    MAGIC,
    OP_CHANNEL,
    OP_CHUNK,
    OP_CHUNK_INDEX,
    OP_FOOTER,
    OP_HEADER,
    OP_MESSAGE,
    OP_SCHEMA,
    OP_STATISTICS,
    _Channel,
    _decompress,
    _msgtype,
    _parse_channel,
    _parse_chunk_header,
    _parse_schema,
    _read_string,
    _records,
    _Schema,
)
from belvedere.bags._model import BagError, BagMessage, Connection
from belvedere.bags._ros1 import ChunkStats

__all__ = ["McapBag"]


@dataclass(frozen=True, slots=True)
class _ChunkRef:
    pos: int
    """Where the chunk record starts."""
    start: int
    end: int
    compression: str
    compressed: int
    uncompressed: int


class McapBag:
    """An MCAP file, open for reading (its summary, or a scan when it has none)."""

    format: Final = "mcap"

    def __init__(self, path: Path) -> None:
        self.path = path
        try:
            self._f: BinaryIO = path.open("rb")
        except OSError as err:
            msg = f"cannot read {path}: {err.strerror or err}"
            raise BagError(msg) from None
        try:
            self._open()
        except (struct.error, UnicodeDecodeError, IndexError) as err:
            self._f.close()
            msg = f"cannot read {path}: a damaged MCAP record ({err})"
            raise BagError(msg) from None
        except BaseException:
            self._f.close()
            raise

    def _open(self) -> None:
        f = self._f
        head = f.read(8 + 9)
        if head[:8] != MAGIC:
            msg = f"{self.path} is not an MCAP file"
            raise BagError(msg)
        if len(head) < 17 or head[8] != OP_HEADER:
            msg = f"{self.path} is not a whole MCAP file (its header is cut short)"
            raise BagError(msg)
        (length,) = _U64.unpack_from(head, 9)
        header = f.read(length)
        if len(header) != length:
            msg = f"{self.path} is not a whole MCAP file (its header is cut short)"
            raise BagError(msg)
        self.profile, _ = _read_string(header, 0)
        self.data_start = 17 + length
        self.version = f"MCAP ({self.profile or 'no'} profile)"
        self._schemas: dict[int, _Schema] = {}
        self._channels: dict[int, _Channel] = {}
        self._chunks: list[_ChunkRef] = []
        self._loose: list[tuple[int, int, int, int]] = []
        """Messages outside chunks: (time, channel, data position, data length)."""
        self.counts: dict[int, int] = defaultdict(int)
        size = self.path.stat().st_size
        f.seek(max(0, size - 8 - 29))
        tail = f.read()
        summary_start = 0
        if len(tail) == 37 and tail[-8:] == MAGIC and tail[0] == OP_FOOTER:
            (summary_start,) = _U64.unpack_from(tail, 9)
        else:
            msg = f"{self.path} is not a whole MCAP file (its recording did not end cleanly)"
            raise BagError(msg, hint=f"belvedere bag reindex {self.path}")
        if summary_start:
            f.seek(summary_start)
            self._read_summary(f.read(size - 37 - summary_start))
        if not self._chunks and not self.counts:
            self._scan(size - 37)
        self.start_ns = min((c.start for c in self._chunks), default=0)
        self.end_ns = max((c.end for c in self._chunks), default=0)
        if self._loose:
            self.start_ns = min(self.start_ns or 2**64, min(t for t, *_ in self._loose))
            self.end_ns = max(self.end_ns, max(t for t, *_ in self._loose))

    def _read_summary(self, buf: bytes) -> None:
        for op, start, end in _records(buf):
            body = buf[start:end]
            if op == OP_SCHEMA:
                schema = _parse_schema(body)
                self._schemas[schema.id] = schema
            elif op == OP_CHANNEL:
                channel = _parse_channel(body)
                self._channels[channel.id] = channel
            elif op == OP_CHUNK_INDEX:
                cstart, cend, pos = struct.unpack_from("<QQQ", body, 0)
                (olen,) = _U32.unpack_from(body, 32)
                at = 36 + olen + 8
                compression, at = _read_string(body, at)
                compressed, uncompressed = struct.unpack_from("<QQ", body, at)
                self._chunks.append(
                    _ChunkRef(pos, cstart, cend, compression, compressed, uncompressed)
                )
            elif op == OP_STATISTICS:
                (n,) = _U32.unpack_from(body, 42)
                for i in range(n // 10):
                    cid, count = struct.unpack_from("<HQ", body, 46 + 10 * i)
                    self.counts[cid] = count

    def _scan(self, end: int) -> None:
        """Find schemas, channels, chunks and messages by reading the data section."""
        f = self._f
        f.seek(self.data_start)
        buf = f.read(end - self.data_start)
        for op, start, stop in _records(buf):
            if op == OP_SCHEMA:
                schema = _parse_schema(buf[start:stop])
                self._schemas[schema.id] = schema
            elif op == OP_CHANNEL:
                channel = _parse_channel(buf[start:stop])
                self._channels[channel.id] = channel
            elif op == OP_MESSAGE:
                cid, _, stamp, _ = _MESSAGE.unpack_from(buf, start)
                pos = self.data_start + start + _MESSAGE.size
                self._loose.append((stamp, cid, pos, stop - start - _MESSAGE.size))
                self.counts[cid] += 1
            elif op == OP_CHUNK:
                cstart, cend, size, _, compression, compressed, _ = _parse_chunk_header(
                    buf[start:stop]
                )
                ref = _ChunkRef(
                    self.data_start + start - 9, cstart, cend, compression, compressed, size
                )
                self._chunks.append(ref)
                for rop, rstart, rend, raw in self._chunk_records(ref):
                    if rop == OP_SCHEMA:
                        schema = _parse_schema(raw[rstart:rend])
                        self._schemas[schema.id] = schema
                    elif rop == OP_CHANNEL:
                        channel = _parse_channel(raw[rstart:rend])
                        self._channels[channel.id] = channel
                    elif rop == OP_MESSAGE:
                        self.counts[_U16.unpack_from(raw, rstart)[0]] += 1

    def _chunk_data(self, ref: _ChunkRef) -> bytes:
        f = self._f
        # start, end, size (8 bytes each), crc (4), the compression's name, its data's size
        f.seek(ref.pos + 9 + 28 + 4 + len(ref.compression.encode()) + 8)
        raw = _decompress(ref.compression, f.read(ref.compressed), ref.uncompressed)
        if raw is None or len(raw) != ref.uncompressed:
            msg = f"cannot read {self.path}: a damaged chunk at byte {ref.pos}"
            raise BagError(msg)
        return raw

    def _chunk_records(self, ref: _ChunkRef) -> Iterator[tuple[int, int, int, bytes]]:
        raw = self._chunk_data(ref)
        for op, start, end in _records(raw):
            yield op, start, end, raw

    # --- the common face ------------------------------------------------------------------
    @property
    def connections(self) -> list[Connection]:
        out = []
        for channel in self._channels.values():
            schema = self._schemas.get(channel.schema_id)
            meta = channel.metadata
            encoding = "ros1" if channel.encoding == "ros1" else "cdr"
            latching = meta.get("latching") == "1" or "durability: 1" in meta.get(
                "offered_qos_profiles", ""
            )
            out.append(
                Connection(
                    id=channel.id,
                    topic=channel.topic,
                    msgtype=_msgtype(schema.name) if schema else "",
                    encoding=encoding,
                    md5sum=meta.get("md5sum", ""),
                    definition=schema.data.decode(errors="replace") if schema else "",
                    callerid=meta.get("callerid"),
                    latching=latching,
                )
            )
        return out

    @property
    def size(self) -> int:
        return self.path.stat().st_size

    def chunks(self) -> list[ChunkStats]:
        return [
            ChunkStats(c.compression or "none", c.compressed, c.uncompressed) for c in self._chunks
        ]

    def messages(
        self,
        connections: Iterable[Connection] | None = None,
        start_ns: int | None = None,
        stop_ns: int | None = None,
    ) -> Iterator[BagMessage]:
        conns = {c.id: c for c in self.connections}
        if connections is not None:
            wanted = {c.id for c in connections}
            conns = {k: v for k, v in conns.items() if k in wanted}
        lo = 0 if start_ns is None else start_ns
        hi = 2**64 if stop_ns is None else stop_ns
        sources = [
            self._chunk_messages(ref, conns, lo, hi)
            for ref in sorted(self._chunks, key=lambda r: (r.start, r.pos))
            if ref.end >= lo and ref.start < hi
        ]
        if self._loose:
            sources.append(self._loose_messages(conns, lo, hi))
        for item in heapq.merge(*sources, key=lambda m: m[0]):
            if item[1] is not None:
                yield item[1]

    def _chunk_messages(
        self, ref: _ChunkRef, conns: dict[int, Connection], lo: int, hi: int
    ) -> Iterator[tuple[int, BagMessage | None]]:
        yield ref.start, None  # a chunk is read only when the merge reaches it
        found = []
        for op, start, end, raw in self._chunk_records(ref):
            if op != OP_MESSAGE:
                continue
            cid, _, stamp, _ = _MESSAGE.unpack_from(raw, start)
            conn = conns.get(cid)
            if conn is not None and lo <= stamp < hi:
                found.append(BagMessage(conn, stamp, raw[start + _MESSAGE.size : end]))
        found.sort(key=lambda m: m.stamp_ns)
        for message in found:
            yield message.stamp_ns, message

    def _loose_messages(
        self, conns: dict[int, Connection], lo: int, hi: int
    ) -> Iterator[tuple[int, BagMessage | None]]:
        for stamp, cid, pos, length in sorted(self._loose):
            conn = conns.get(cid)
            if conn is None or not lo <= stamp < hi:
                continue
            self._f.seek(pos)
            yield stamp, BagMessage(conn, stamp, self._f.read(length))

    def close(self) -> None:
        self._f.close()
