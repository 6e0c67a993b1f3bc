"""Repairing ROS 1 bags whose recording was cut short (see :mod:`belvedere.bags._ros1`):
every whole chunk read from the start, and the index written again."""

from __future__ import annotations

import os
import shutil
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import BinaryIO

from belvedere.bags._model import BagError
from belvedere.bags._ros1 import (
    _U32,
    _U64,
    MAGIC,
    OP_BAGHEADER,
    OP_CHUNK,
    OP_CHUNK_INFO,
    OP_CONNECTION,
    OP_IDXDATA,
    OP_MSGDATA,
    _chunk_info,
    _decompress,
    _fields,
    _index_record,
    _parse_fields,
    _read_header,
    _read_u32,
    _record,
    _unpack_time,
)

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
    was_indexed: bool
    dropped_bytes: int
    """Bytes after the last whole chunk (a chunk the recording did not finish)."""


def scan_ros1(path: Path) -> Ros1Scan:
    """Read every whole chunk of a ROS 1 bag (format 2.0), indexed or not."""
    with path.open("rb") as f:
        magic = f.readline()
        if magic != MAGIC:
            what = "a ROS 1 bag of format 1.2" if magic.startswith(b"#ROSBAG V1") else None
            msg = f"{path} is {what or 'not a ROS 1 bag (format 2.0)'}"
            raise BagError(msg)
        fields, _ = _read_header(f)
        if fields is None or fields.get("op") != bytes([OP_BAGHEADER]):
            msg = f"{path}: the bag header is damaged"
            raise BagError(msg)
        length = _read_u32(f)
        if length is None:
            msg = f"{path}: the bag header is cut short"
            raise BagError(msg)
        f.seek(length, os.SEEK_CUR)
        index_pos = _U64.unpack(fields.get("index_pos", b"\0" * 8))[0]
        header_end = f.tell()
        size = path.stat().st_size
        chunks: list[_Chunk] = []
        connections: dict[int, tuple[bytes, bytes]] = {}
        good_end = header_end
        while True:
            pos = f.tell()
            fields, _ = _read_header(f)
            data_len = _read_u32(f) if fields is not None else None
            if fields is None or data_len is None or f.tell() + data_len > size:
                break
            op = fields.get("op", b"")
            if op == bytes([OP_CHUNK]):
                raw = _decompress(fields.get("compression", b"none"), f.read(data_len))
                want = _U32.unpack(fields.get("size", b"\xff" * 4))[0]
                if raw is None or len(raw) != want:
                    break
                chunk = _Chunk(pos, f.tell())
                if not _scan_chunk(raw, chunk, connections):
                    break
                chunks.append(chunk)
                good_end = f.tell()
            elif op == bytes([OP_CONNECTION]):
                data = f.read(data_len)
                conn = _U32.unpack(fields.get("conn", b"\0\0\0\0"))[0]
                connections.setdefault(conn, (fields.get("topic", b""), data))
                good_end = f.tell()
            elif op in (bytes([OP_IDXDATA]), bytes([OP_CHUNK_INFO])):
                f.seek(data_len, os.SEEK_CUR)
                good_end = f.tell()
            else:
                break
        return Ros1Scan(header_end, chunks, connections, index_pos != 0, size - good_end)


def _scan_chunk(raw: bytes, chunk: _Chunk, connections: dict[int, tuple[bytes, bytes]]) -> bool:
    pos = 0
    end = len(raw)
    while pos < end:
        offset = pos
        if pos + 4 > end:
            return False
        (hlen,) = _U32.unpack_from(raw, pos)
        fields = _parse_fields(raw[pos + 4 : pos + 4 + hlen])
        pos += 4 + hlen
        if fields is None or pos + 4 > end:
            return False
        (dlen,) = _U32.unpack_from(raw, pos)
        pos += 4
        if pos + dlen > end:
            return False
        op = fields.get("op", b"")
        conn = _U32.unpack(fields.get("conn", b"\0\0\0\0"))[0]
        if op == bytes([OP_MSGDATA]):
            chunk.index[conn].append((_unpack_time(fields["time"]), offset))
        elif op == bytes([OP_CONNECTION]):
            connections.setdefault(conn, (fields.get("topic", b""), raw[pos : pos + dlen]))
        pos += dlen
    return True


def write_indexed(source: Path, scan: Ros1Scan, target: BinaryIO) -> int:
    """Write the bag ``scan`` read from ``source`` to ``target``, whole chunks only, with its
    index. Returns how many messages it holds."""
    total = 0
    known = scan.connections
    with source.open("rb") as f:
        header = f.read(scan.header_end)
        target.write(header)
        placed: list[tuple[int, dict[int, list[tuple[int, int]]]]] = []
        for chunk in scan.chunks:
            f.seek(chunk.start)
            pos = target.tell()
            target.write(f.read(chunk.end - chunk.start))
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
    # The bag header keeps its place and length: its padding absorbs the new numbers.
    target.seek(len(MAGIC))
    fields = _fields(
        {
            "op": bytes([OP_BAGHEADER]),
            "index_pos": _U64.pack(index_pos),
            "conn_count": _U32.pack(len(known)),
            "chunk_count": _U32.pack(len(placed)),
        }
    )
    padding = scan.header_end - len(MAGIC) - len(fields) - 4
    target.write(fields + _U32.pack(padding) + b" " * padding)
    return total


def reindex_ros1(path: Path, output: Path, backup: Path | None) -> tuple[int, int]:
    """Rebuild the index of the bag at ``path`` into ``output`` (which may be ``path``:
    the original is then moved to ``backup`` first). Returns (messages, bytes dropped)."""
    scan = scan_ros1(path)
    source = path
    if backup is not None:
        shutil.move(path, backup)
        source = backup
    temp = output.with_name(f".{output.name}.reindex")
    try:
        with temp.open("wb") as target:
            count = write_indexed(source, scan, target)
        temp.replace(output)
    except OSError as err:
        temp.unlink(missing_ok=True)
        if backup is not None and not path.exists():
            shutil.move(backup, path)
        msg = f"cannot write {output}: {err.strerror or err}"
        raise BagError(msg) from None
    return count, scan.dropped_bytes
