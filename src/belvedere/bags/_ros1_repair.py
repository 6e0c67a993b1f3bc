"""Repairing ROS 1 bags whose recording was cut short (see :mod:`belvedere.bags._ros1`):
every whole chunk read from the start, and the index written again."""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import BinaryIO

from belvedere.bags._input import BagInput, Damaged, Repaired, inflate_chunk, replace_with
from belvedere.bags._model import BagError
from belvedere.bags._ros1 import (
    _U32,
    _U64,
    CODECS,
    HEADER_SIZE,
    MAGIC,
    OP_BAGHEADER,
    OP_CHUNK,
    OP_CHUNK_INFO,
    OP_CONNECTION,
    OP_IDXDATA,
    OP_MSGDATA,
    _chunk_info,
    _fields,
    _index_record,
    _record,
    op_of,
    read_record_header,
    record_at,
    text_field,
    time_field,
    u32_field,
)
from belvedere.bags._ros1 import field as header_field

__all__ = ["Ros1Scan", "reindex_ros1", "scan_ros1", "write_indexed"]


@dataclass
class _Chunk:
    start: int
    """Where the chunk record begins in the source."""
    end: int
    """Where it ends."""
    index: dict[int, list[tuple[int, int]]] = field(default_factory=lambda: defaultdict(list))
    """connection id → [(time, offset in the chunk's data)]"""


@dataclass
class Ros1Scan:
    """What a bag's records hold, read one by one from the start."""

    header_end: int
    chunks: list[_Chunk]
    connections: dict[int, tuple[bytes, bytes]]
    """id → (topic, connection header bytes)"""
    good_end: int
    """Where the last whole record the repair keeps ends."""
    damage: Damaged | None
    """Why reading stopped before the end of the file (a record cut short, or damaged)."""


def scan_ros1(inp: BagInput) -> Ros1Scan:
    """Read every whole chunk of a ROS 1 bag (format 2.0), indexed or not, up to the end of
    the file or the first record that is cut short or damaged.

    Raises:
        BagError: the bag header itself is damaged.
    """
    pos = len(MAGIC)
    try:
        fields, data_pos, data_len = read_record_header(inp, pos)
        if op_of(fields, pos) != OP_BAGHEADER:
            raise Damaged(pos, "no bag header record after the magic line")
    except Damaged as err:
        raise inp.error(err.at, err.text) from None
    header_end = data_pos + data_len
    chunks: list[_Chunk] = []
    connections: dict[int, tuple[bytes, bytes]] = {}
    pos = header_end
    damage = None
    while pos < inp.size:
        try:
            fields, data_pos, data_len = read_record_header(inp, pos)
            op = op_of(fields, pos)
            if op == OP_CHUNK:
                compression = text_field(fields, "compression", pos)
                size = u32_field(fields, "size", pos)
                data = inp.read(data_pos, data_len, "chunk data")
                chunk = _Chunk(pos, data_pos + data_len)
                _scan_chunk(inflate_chunk(compression, CODECS, data, size, pos), chunk, connections)
                chunks.append(chunk)
            elif op == OP_CONNECTION:
                conn = u32_field(fields, "conn", pos)
                topic = header_field(fields, "topic", 0, pos)
                data = inp.read(data_pos, data_len, "connection data")
                connections.setdefault(conn, (topic, data))
            elif op not in (OP_IDXDATA, OP_CHUNK_INFO):
                raise Damaged(pos, f"a record of unknown kind {op} (op)")
        except Damaged as err:
            damage = err
            break
        pos = data_pos + data_len
    return Ros1Scan(header_end, chunks, connections, pos, damage)


def _scan_chunk(raw: bytes, chunk: _Chunk, connections: dict[int, tuple[bytes, bytes]]) -> None:
    """Index the records of a chunk's inflated data ``raw``.

    Raises:
        Damaged: (at the chunk) a record in it is not what it declares.
    """
    pos = 0
    try:
        while pos < len(raw):
            fields, start, end = record_at(raw, pos)
            op = op_of(fields, pos)
            if op == OP_MSGDATA:
                conn = u32_field(fields, "conn", pos)
                chunk.index[conn].append((time_field(fields, "time", pos), pos))
            elif op == OP_CONNECTION:
                conn = u32_field(fields, "conn", pos)
                topic = header_field(fields, "topic", 0, pos)
                connections.setdefault(conn, (topic, raw[start:end]))
            pos = end
    except Damaged as err:
        text = f"chunk, at byte {err.at:,} of its data: {err.text}"
        raise Damaged(chunk.start, text) from None


def write_indexed(inp: BagInput, scan: Ros1Scan, target: BinaryIO) -> int:
    """Write the bag ``scan`` read from ``inp`` to ``target``, whole chunks only, with its
    index. Returns how many messages it holds."""
    total = 0
    known = scan.connections
    # The bag header keeps its length (rosbag's is 4104 bytes) when the new numbers fit in
    # its padding; else it is rosbag's.
    header_size = scan.header_end - len(MAGIC)
    if header_size < _bag_header_size(0, 0, 0):
        header_size = HEADER_SIZE + 8
    target.write(MAGIC + b"\0" * header_size)
    placed: list[tuple[int, dict[int, list[tuple[int, int]]]]] = []
    for chunk in scan.chunks:
        pos = target.tell()
        target.write(inp.read(chunk.start, chunk.end - chunk.start, "chunk"))
        index = {c: sorted(e) for c, e in sorted(chunk.index.items()) if c in known}
        for conn, entries in index.items():
            target.write(_index_record(conn, entries))
            total += len(entries)
        placed.append((pos, index))
    index_pos = target.tell()
    for conn, (topic, data) in sorted(known.items()):
        target.write(
            _record({"op": bytes([OP_CONNECTION]), "conn": _U32.pack(conn), "topic": topic}, data)
        )
    for pos, index in placed:
        times = [t for entries in index.values() for t, _ in entries]
        target.write(_chunk_info(pos, min(times, default=0), max(times, default=0), index))
    target.seek(len(MAGIC))
    fields = _header_fields(index_pos, len(known), len(placed))
    padding = header_size - len(fields) - 4
    target.write(fields + _U32.pack(padding) + b" " * padding)
    return total


def _header_fields(index_pos: int, conns: int, chunks: int) -> bytes:
    return _fields(
        {
            "op": bytes([OP_BAGHEADER]),
            "index_pos": _U64.pack(index_pos),
            "conn_count": _U32.pack(conns),
            "chunk_count": _U32.pack(chunks),
        }
    )


def _bag_header_size(index_pos: int, conns: int, chunks: int) -> int:
    """The bytes of a bag header record without padding."""
    return len(_header_fields(index_pos, conns, chunks)) + 4


def reindex_ros1(inp: BagInput, output: Path, backup: Path | None) -> Repaired:
    """Rebuild the index of the bag ``inp`` into ``output`` (which may be its path: the
    original is then moved to ``backup`` first, and kept).

    Raises:
        BagError: its bag header is damaged, or no whole chunk comes before the first
            damaged or cut-short record (``x.bag: offset N: …``); the file is left as it was.
    """
    scan = scan_ros1(inp)
    count = sum(len(e) for c in scan.chunks for e in c.index.values())
    damage = scan.damage
    if damage is not None and not count:
        msg = f"{inp.path}: offset {damage.at}: {damage.text}: no whole chunk before it to keep"
        raise BagError(msg)
    count = replace_with(inp, output, backup, lambda target: write_indexed(inp, scan, target))
    dropped = inp.size - scan.good_end
    return Repaired(output, count, dropped, _reason(inp, damage))


def _reason(inp: BagInput, damage: Damaged | None) -> str | None:
    """Why the repair stopped early, when it was not the end of a recording cut short."""
    if damage is None or damage.truncated:
        return None
    return f"{inp.path}: offset {damage.at}: {damage.text}"
