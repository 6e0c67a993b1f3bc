"""Reading MCAP files (see :mod:`belvedere.bags._mcap`): from their summary, or by reading
the data section record by record when they have none.

Every declared length and offset is checked against the file before it is used, every chunk
is inflated to at most its declared size (:func:`belvedere.bounded.inflate`) and checked
against its CRC, and:

- a damaged header, footer or summary is one error, ``x.mcap: offset N: …`` (``bag
  reindex`` writes the summary again from the data);
- a damaged chunk is one warning (the first; the others are counted) and its messages are
  skipped: the rest of the file still reads.
"""

from __future__ import annotations

import functools
from collections import defaultdict
from collections.abc import Iterator
from typing import Final

from belvedere.bags._chunked import ChunkedBag, Timed
from belvedere.bags._input import BagInput, Damaged
from belvedere.bags._mcap import (
    _INVALID,
    _MESSAGE,
    _RECORD,
    _U64,
    MAGIC,
    OP_CHANNEL,
    OP_CHUNK,
    OP_CHUNK_INDEX,
    OP_DATA_END,
    OP_FOOTER,
    OP_HEADER,
    OP_MESSAGE,
    OP_SCHEMA,
    OP_STATISTICS,
    _Channel,
    _ChunkRef,
    _fixed,
    _inflated_chunk,
    _message_head,
    _msgtype,
    _parse_channel,
    _parse_chunk_index,
    _parse_schema,
    _parse_statistics,
    _read_string,
    _records,
    _Schema,
)
from belvedere.bags._model import BagError, BagMessage, Connection
from belvedere.bags._ros1 import ChunkStats

__all__ = ["McapBag"]

_TAIL: Final = 9 + 20 + 8
"""The footer record and the closing magic."""


class McapBag(ChunkedBag):
    """An MCAP file, open for reading (its summary, or a scan when it has none).

    Raises:
        BagError: not a whole MCAP file, or its header, footer or summary is damaged
            (``x.mcap: offset N: …``).
    """

    format: Final = "mcap"

    def __init__(self, inp: BagInput) -> None:
        super().__init__(inp)
        self._schemas: dict[int, _Schema] = {}
        self._channels: dict[int, _Channel] = {}
        self._chunks: list[_ChunkRef] = []
        self._loose: list[tuple[int, int, int, int]] = []
        """Messages outside chunks: (time, channel, data position, data length)."""
        self.counts: dict[int, int] = defaultdict(int)
        self._opened()
        self.start_ns = min((c.start for c in self._chunks), default=0)
        self.end_ns = max((c.end for c in self._chunks), default=0)
        if self._loose:
            self.start_ns = min(self.start_ns or 2**64, min(t for t, *_ in self._loose))
            self.end_ns = max(self.end_ns, max(t for t, *_ in self._loose))

    def _open(self) -> None:
        inp = self._in
        inp.f.seek(len(MAGIC))
        head = inp.f.read(9)
        if len(head) < 9 or head[0] != OP_HEADER:
            msg = f"{self.path} is not a whole MCAP file (its header is cut short)"
            raise BagError(msg)
        (length,) = _U64.unpack_from(head, 1)
        header = inp.read(17, length, "the header record")
        self.profile, _ = _read_string(header, 0, "header: profile", 17)
        self.data_start = 17 + length
        self.version = f"MCAP ({self.profile or 'no'} profile)"
        size = inp.size
        whole = size - _TAIL >= self.data_start
        tail = inp.read(size - _TAIL, _TAIL, "the footer") if whole else b""
        if not whole or tail[0] != OP_FOOTER or tail[-8:] != MAGIC:
            msg = f"{self.path} is not a whole MCAP file (its recording did not end cleanly)"
            raise BagError(msg, hint=f"belvedere bag reindex {self.path}")
        self._hint = f"belvedere bag reindex {self.path} writes the summary again from the data"
        self._data_end = size - _TAIL
        (summary_start,) = _U64.unpack_from(tail, 9)
        if summary_start:
            if not self.data_start <= summary_start <= size - _TAIL:
                text = (
                    f"footer: the summary is said to start at offset {summary_start:,}, outside "
                    f"the file's records (offsets {self.data_start:,} to {size - _TAIL:,})"
                )
                raise Damaged(size - _TAIL, text)
            self._data_end = summary_start
            length = size - _TAIL - summary_start
            self._read_summary(inp.read(summary_start, length, "the summary"), summary_start)
        if not self._chunks and not self.counts:
            self._scan()

    def _read_summary(self, buf: bytes, base: int) -> None:
        for op, start, end in _records(buf, base):
            body = buf[start:end]
            if op == OP_SCHEMA:
                schema = _parse_schema(body, base + start)
                self._schemas[schema.id] = schema
            elif op == OP_CHANNEL:
                channel = _parse_channel(body, base + start)
                self._channels[channel.id] = channel
            elif op == OP_CHUNK_INDEX:
                self._chunks.append(_parse_chunk_index(body, base + start))
            elif op == OP_STATISTICS:
                self.counts.update(_parse_statistics(body, base + start))

    def _scan(self) -> None:
        """Find schemas, channels, chunks and messages by reading the data section, record
        by record (a file written without a summary)."""
        inp = self._in
        end = self._data_end
        pos = self.data_start
        while pos < end:
            op, length = _RECORD.unpack(inp.read(pos, 9, "a record", end=end))
            body = pos + 9
            inp.check(body, length, "a record", end=end)
            if op == OP_DATA_END:
                break
            if not op:
                raise Damaged(pos, _INVALID)
            if op == OP_SCHEMA:
                schema = _parse_schema(inp.read(body, length, "a schema record"), body)
                self._schemas[schema.id] = schema
            elif op == OP_CHANNEL:
                channel = _parse_channel(inp.read(body, length, "a channel record"), body)
                self._channels[channel.id] = channel
            elif op == OP_MESSAGE:
                cid, stamp = _message_head(inp, body, length)
                self._loose.append((stamp, cid, body + _MESSAGE.size, length - _MESSAGE.size))
                self.counts[cid] += 1
            elif op == OP_CHUNK:
                self._scan_chunk(pos)
            pos = body + length

    def _scan_chunk(self, pos: int) -> None:
        try:
            ref, raw = self._chunk(_ChunkRef(pos, 0, 0, "", 0, 0))
        except Damaged as err:
            self.skipped.skip(pos, err.at, f"{err.text}; skipping its messages")
            return
        self._chunks.append(ref)
        try:
            for op, start, end in _records(raw, 0):
                body = raw[start:end]
                if op == OP_SCHEMA:
                    schema = _parse_schema(body, start)
                    self._schemas[schema.id] = schema
                elif op == OP_CHANNEL:
                    channel = _parse_channel(body, start)
                    self._channels[channel.id] = channel
                elif op == OP_MESSAGE:
                    _fixed(body, OP_MESSAGE, "a message", start)
                    self.counts[int.from_bytes(body[:2], "little")] += 1
        except Damaged as err:
            text = f"chunk, at byte {err.at:,} of its data: {err.text}; skipping the rest"
            self.skipped.skip(pos, pos, text)

    def _chunk(self, ref: _ChunkRef) -> tuple[_ChunkRef, bytes]:
        """The chunk at ``ref.pos`` (as its own record describes it) and its inflated data.

        Raises:
            Damaged: at the chunk record's offset.
        """
        inp = self._in
        pos = ref.pos
        if not self.data_start <= pos < self._data_end:
            text = (
                f"chunk index: its chunk is said to start at offset {pos:,}, outside the "
                f"data section (offsets {self.data_start:,} to {self._data_end:,})"
            )
            raise Damaged(ref.at or pos, text)
        op, length = _RECORD.unpack(inp.read(pos, 9, "a chunk record", end=self._data_end))
        if op != OP_CHUNK:
            text = f"chunk index: offset {pos:,} holds a record of kind {op:#04x}, not a chunk"
            raise Damaged(ref.at or pos, text)
        return _inflated_chunk(inp.read(pos + 9, length, "a chunk record", end=self._data_end), pos)

    # --- the common face ------------------------------------------------------------------
    @property
    def connections(self) -> list[Connection]:
        out = []
        for channel in self._channels.values():
            schema = self._schemas.get(channel.schema_id)
            meta = channel.metadata
            # Another encoding (json, protobuf…) is kept: the Decoder skips it, saying so.
            encoding = "cdr" if channel.encoding in ("cdr", "") else channel.encoding
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

    def chunks(self) -> list[ChunkStats]:
        return [
            ChunkStats(c.compression or "none", c.compressed, c.uncompressed) for c in self._chunks
        ]

    def _by_id(self) -> dict[int, Connection]:
        return {c.id: c for c in self.connections}

    def _sources(self, conns: dict[int, Connection], lo: int, hi: int) -> list[Iterator[Timed]]:
        sources = [
            self._chunk_messages(
                ref.pos,
                ref.start,
                functools.partial(self._chunk_data, ref),
                _parse_chunk,
                conns,
                lo,
                hi,
            )
            for ref in sorted(self._chunks, key=lambda r: (r.start, r.pos))
            if ref.end >= lo and ref.start < hi
        ]
        if self._loose:
            sources.append(self._loose_messages(conns, lo, hi))
        return sources

    def _chunk_data(self, ref: _ChunkRef) -> bytes:
        return self._chunk(ref)[1]

    def _loose_messages(self, conns: dict[int, Connection], lo: int, hi: int) -> Iterator[Timed]:
        for stamp, cid, pos, length in sorted(self._loose):
            conn = conns.get(cid)
            if conn is None or not lo <= stamp < hi:
                continue
            try:
                data = self._in.read(pos, length, "a message")
            except Damaged as err:  # the file changed since it was opened
                self.skipped.skip(pos, err.at, f"{err.text}; skipping it")
                continue
            yield stamp, BagMessage(conn, stamp, data)


def _parse_chunk(
    raw: bytes, conns: dict[int, Connection], lo: int, hi: int, found: list[BagMessage]
) -> None:
    """Add the messages of a chunk's inflated data ``raw`` on ``conns`` in [lo, hi) to
    ``found``.

    Raises:
        Damaged: a record that is not what it declares (at its byte in ``raw``); the
            messages before it are in ``found``.
    """
    unpack_record = _RECORD.unpack_from
    unpack_message = _MESSAGE.unpack_from
    fixed = _MESSAGE.size
    end = len(raw)
    pos = 0
    while pos < end:
        if pos + 9 > end:
            raise Damaged(pos, "a record cut short")
        op, length = unpack_record(raw, pos)
        body = pos + 9
        stop = body + length
        if stop > end:
            raise Damaged(pos, f"a record of {length:,} bytes runs past the chunk")
        if op == OP_MESSAGE:
            if length < fixed:
                _fixed(raw[body:stop], OP_MESSAGE, "a message", body)
            cid, _, stamp, _ = unpack_message(raw, body)
            conn = conns.get(cid)
            if conn is not None and lo <= stamp < hi:
                found.append(BagMessage(conn, stamp, raw[body + fixed : stop]))
        elif not op:
            raise Damaged(pos, _INVALID)
        pos = stop
