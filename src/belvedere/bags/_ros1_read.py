"""Reading indexed ROS 1 bags (format 2.0; see :mod:`belvedere.bags._ros1`).

Opening reads the bag header and the index at its end (connections, and one chunk-info
record per chunk: where the chunk is, its time span, its messages per connection); the
chunks are read when their messages are asked for, one at a time, in time order. Every
declared length and offset is checked against the file before it is used, every chunk is
inflated to at most its declared size (:func:`belvedere.bounded.inflate`), and:

- a damaged bag header or index is one error, ``x.bag: offset N: …`` (``bag reindex``
  rebuilds the index from the chunks);
- a damaged chunk is one warning (the first; the others are counted) and its messages are
  skipped: the rest of the bag still reads.
"""

from __future__ import annotations

import functools
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Final

from rosbags.typesys.msg import normalize_msgtype

from belvedere.bags._chunked import ChunkedBag, Timed
from belvedere.bags._input import BagInput, Damaged, inflate_chunk
from belvedere.bags._model import BagError, BagMessage, Connection
from belvedere.bags._ros1 import (
    _U32,
    CODECS,
    MAGIC,
    OP_BAGHEADER,
    OP_CHUNK,
    OP_CHUNK_INFO,
    OP_CONNECTION,
    OP_MSGDATA,
    ChunkStats,
    op_of,
    parse_fields,
    read_record_header,
    record_at,
    text_field,
    time_field,
    u32_field,
    u64_field,
)

__all__ = ["Ros1Bag"]

_REINDEX: Final = "belvedere bag reindex {path} rebuilds the index from the chunks"


@dataclass(frozen=True, slots=True)
class _ChunkInfo:
    pos: int
    """Where the chunk record starts."""
    start: int
    end: int
    counts: dict[int, int]
    """Messages per connection id."""
    at: int
    """Where the chunk-info record is (in the index)."""


def _topic(name: str) -> str:
    """A topic name without repeated or trailing slashes (as rosbags spells them)."""
    parts = [p for p in name.split("/") if p]
    return ("/" if name.startswith("/") else "") + "/".join(parts)


class Ros1Bag(ChunkedBag):
    """An indexed ROS 1 bag, open for reading.

    Raises:
        BagError: not an indexed ROS 1 bag of format 2.0, or its bag header or index is
            damaged (``x.bag: offset N: …``).
    """

    format: Final = "bag"

    def __init__(self, inp: BagInput) -> None:
        super().__init__(inp)
        self.version = "2.0"
        self._conns: dict[int, Connection] = {}
        self._infos: list[_ChunkInfo] = []
        self.counts: dict[int, int] = {}
        self._opened()
        counted = [i for i in self._infos if i.counts]
        self.start_ns = min((i.start for i in counted), default=0)
        self.end_ns = max((i.end for i in counted), default=0)

    def _open(self) -> None:
        inp = self._in
        pos = len(MAGIC)
        fields, data_pos, data_len = read_record_header(inp, pos)
        if op_of(fields, pos) != OP_BAGHEADER:
            raise Damaged(pos, "no bag header record after the magic line")
        index_pos = u64_field(fields, "index_pos", pos)
        u32_field(fields, "conn_count", pos)
        u32_field(fields, "chunk_count", pos)
        if fields.get("encryptor"):
            name = fields["encryptor"].decode(errors="replace")
            msg = f"{self.path} is encrypted ({name}); belvedere reads unencrypted bags"
            raise BagError(msg)
        self._data_start = data_pos + data_len
        if index_pos == 0:
            msg = f"{self.path} is unindexed (its recording did not end cleanly)"
            raise BagError(msg, hint=f"belvedere bag reindex {self.path}")
        self._hint = _REINDEX.format(path=self.path)
        if not self._data_start <= index_pos <= inp.size:
            text = (
                f"bag header: the index is said to start at offset {index_pos:,}, outside "
                f"the file's data (offsets {self._data_start:,} to {inp.size:,})"
            )
            raise Damaged(pos, text)
        self._index_pos = index_pos
        index = inp.read(index_pos, inp.size - index_pos, "the index")
        at = 0
        while at < len(index):
            fields, start, end = record_at(index, at, index_pos)
            where = index_pos + at
            op = op_of(fields, where)
            if op == OP_CONNECTION:
                self._connection(fields, index[start:end], where, index_pos + start)
            elif op == OP_CHUNK_INFO:
                self._chunk_info(fields, index[start:end], where)
            else:
                raise Damaged(where, f"the index holds a record of kind {op} (op)")
            at = end
        for info in self._infos:
            for conn, n in info.counts.items():
                if conn in self._conns:
                    self.counts[conn] = self.counts.get(conn, 0) + n

    def _connection(self, fields: dict[str, bytes], data: bytes, at: int, data_at: int) -> None:
        conn = u32_field(fields, "conn", at)
        topic = _topic(text_field(fields, "topic", at))
        header = parse_fields(data, 0, len(data), data_at)
        latching = header.get("latching", b"0")
        self._conns.setdefault(
            conn,
            Connection(
                id=conn,
                topic=topic,
                msgtype=normalize_msgtype(text_field(header, "type", data_at)),
                encoding="ros1",
                md5sum=text_field(header, "md5sum", data_at),
                definition=text_field(header, "message_definition", data_at),
                callerid=text_field(header, "callerid", data_at) if "callerid" in header else None,
                latching=latching not in (b"", b"0"),
            ),
        )

    def _chunk_info(self, fields: dict[str, bytes], data: bytes, at: int) -> None:
        version = u32_field(fields, "ver", at)
        if version != 1:
            raise Damaged(at, f"chunk info of version {version}; belvedere reads version 1")
        pos = u64_field(fields, "chunk_pos", at)
        count = u32_field(fields, "count", at)
        if len(data) != 8 * count:
            text = f"chunk info: {len(data):,} bytes of counts for {count:,} connections"
            raise Damaged(at, text)
        counts: dict[int, int] = {}
        for i in range(count):
            conn, n = _U32.unpack_from(data, 8 * i)[0], _U32.unpack_from(data, 8 * i + 4)[0]
            counts[conn] = counts.get(conn, 0) + n
        start = time_field(fields, "start_time", at) if count else 0
        end = time_field(fields, "end_time", at) if count else 0
        self._infos.append(_ChunkInfo(pos, start, end, counts, at))

    # --- the common face ------------------------------------------------------------------
    @property
    def connections(self) -> list[Connection]:
        return list(self._conns.values())

    def chunks(self) -> list[ChunkStats]:
        """Each chunk's compression and sizes (from the chunk records' headers); a damaged
        one is skipped, with a warning."""
        stats = []
        for info in self._infos:
            try:
                fields, _, length = self._chunk_header(info)
                compression = text_field(fields, "compression", info.pos)
                size = u32_field(fields, "size", info.pos)
            except Damaged as err:
                self.skipped.skip(info.pos, err.at, f"{err.text}; left out of the compression line")
                continue
            stats.append(ChunkStats(compression, length, size))
        return stats

    def _chunk_header(self, info: _ChunkInfo) -> tuple[dict[str, bytes], int, int]:
        pos = info.pos
        if not self._data_start <= pos < self._index_pos:
            text = (
                f"chunk info: its chunk is said to start at offset {pos:,}, outside the "
                f"chunks (offsets {self._data_start:,} to {self._index_pos:,})"
            )
            raise Damaged(info.at, text)
        fields, data_pos, data_len = read_record_header(self._in, pos, self._index_pos)
        if op_of(fields, pos) != OP_CHUNK:
            raise Damaged(pos, "the chunk info's offset holds no chunk record")
        return fields, data_pos, data_len

    def _chunk_data(self, info: _ChunkInfo) -> bytes:
        fields, data_pos, data_len = self._chunk_header(info)
        pos = info.pos
        compression = text_field(fields, "compression", pos)
        size = u32_field(fields, "size", pos)
        data = self._in.read(data_pos, data_len, "chunk data")
        return inflate_chunk(compression, CODECS, data, size, pos)

    def _by_id(self) -> dict[int, Connection]:
        return self._conns

    def _sources(self, conns: dict[int, Connection], lo: int, hi: int) -> list[Iterator[Timed]]:
        return [
            self._chunk_messages(
                info.pos,
                info.start,
                functools.partial(self._chunk_data, info),
                _parse_chunk,
                conns,
                lo,
                hi,
            )
            for info in sorted(self._infos, key=lambda i: (i.start, i.pos))
            if info.end >= lo and info.start < hi and any(c in conns for c in info.counts)
        ]


def _parse_chunk(
    raw: bytes, conns: dict[int, Connection], lo: int, hi: int, found: list[BagMessage]
) -> None:
    """Add the messages of a chunk's inflated data ``raw`` on ``conns`` in [lo, hi) to
    ``found``.

    The header of each message record is read here rather than through
    :func:`parse_fields`: this loop is the reading speed.

    Raises:
        Damaged: a record that is not what it declares (at its byte in ``raw``); the
            messages before it are in ``found``.
    """
    unpack = _U32.unpack_from
    end = len(raw)
    pos = 0
    while pos < end:
        start = pos
        if pos + 4 > end:
            raise Damaged(start, "a record cut short")
        (hlen,) = unpack(raw, pos)
        p = pos + 4
        hend = p + hlen
        if hend + 4 > end:
            raise Damaged(start, f"a record header of {hlen:,} bytes runs past the chunk")
        op = conn = stamp = -1
        while p < hend:
            if p + 4 > hend:
                raise Damaged(start, "record header: a field's length is cut short")
            (size,) = unpack(raw, p)
            p += 4
            q = p + size
            if q > hend:
                raise Damaged(start, f"record header: a field of {size:,} bytes runs past it")
            if size == 4 and raw[p : p + 3] == b"op=":
                op = raw[p + 3]
            elif size == 9 and raw[p : p + 5] == b"conn=":
                (conn,) = unpack(raw, p + 5)
            elif size == 13 and raw[p : p + 5] == b"time=":
                stamp = unpack(raw, p + 5)[0] * 1_000_000_000 + unpack(raw, p + 9)[0]
            p = q
        (dlen,) = unpack(raw, hend)
        data = hend + 4
        pos = data + dlen
        if pos > end:
            raise Damaged(start, f"a record's data of {dlen:,} bytes runs past the chunk")
        if op == OP_MSGDATA:
            if conn < 0 or stamp < 0:
                missing = "conn" if conn < 0 else "time"
                raise Damaged(start, f"a message record without its '{missing}' field")
            connection = conns.get(conn)
            if connection is not None and lo <= stamp < hi:
                found.append(BagMessage(connection, stamp, raw[data:pos]))
        elif op < 0:
            raise Damaged(start, "a record without its 'op' field")
