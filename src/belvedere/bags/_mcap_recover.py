"""Recovering MCAP files whose recording was cut short (see :mod:`belvedere.bags._mcap`)."""

from __future__ import annotations

import shutil
import struct
import zlib
from collections import defaultdict
from pathlib import Path

from belvedere.bags._mcap import (
    _MESSAGE,
    _U64,
    MAGIC,
    OP_CHANNEL,
    OP_CHUNK,
    OP_DATA_END,
    OP_FOOTER,
    OP_HEADER,
    OP_MESSAGE,
    OP_SCHEMA,
    _chunk_index,
    _decompress,
    _message_indexes,
    _parse_channel,
    _parse_chunk_header,
    _parse_schema,
    _records,
    _Summary,
)
from belvedere.bags._mcap_read import _ChunkRef
from belvedere.bags._model import BagError

__all__ = ["recover_mcap"]


def recover_mcap(path: Path, output: Path, backup: Path | None) -> tuple[int, int]:
    """Write the whole chunks (and loose records) of the MCAP file at ``path`` to ``output``
    with a new summary (``output`` may be ``path``: the original is moved to ``backup``
    first). Returns (messages kept, bytes dropped)."""
    with path.open("rb") as f:
        data = f.read()
    if data[:8] != MAGIC or len(data) < 17 or data[8] != OP_HEADER:
        msg = f"{path} is not an MCAP file"
        raise BagError(msg)
    (hlen,) = _U64.unpack_from(data, 9)
    data_start = 17 + hlen
    summary = _Summary()
    kept: list[tuple[int, int, dict[int, list[tuple[int, int]]] | None, _ChunkRef | None]] = []
    good_end = data_start
    for op, start, end in _records(data, data_start):
        body = data[start:end]
        if op in (OP_DATA_END, OP_FOOTER) or op > 0x0F:
            break
        try:
            if op == OP_SCHEMA:
                schema = _parse_schema(body)
                summary.schemas[schema.id] = schema
                kept.append((start - 9, end, None, None))
            elif op == OP_CHANNEL:
                channel = _parse_channel(body)
                summary.channels[channel.id] = channel
                kept.append((start - 9, end, None, None))
            elif op == OP_MESSAGE:
                cid, _, stamp, _ = _MESSAGE.unpack_from(body, 0)
                summary.add_message(cid, stamp)
                kept.append((start - 9, end, None, None))
            elif op == OP_CHUNK:
                cstart, cend, size, crc, compression, compressed, offset = _parse_chunk_header(body)
                raw = _decompress(compression, body[offset : offset + compressed], size)
                if raw is None or len(raw) != size or (crc and zlib.crc32(raw) != crc):
                    break
                index: dict[int, list[tuple[int, int]]] = defaultdict(list)
                for rop, rstart, rend in _records(raw):
                    if rop == OP_SCHEMA:
                        schema = _parse_schema(raw[rstart:rend])
                        summary.schemas[schema.id] = schema
                    elif rop == OP_CHANNEL:
                        channel = _parse_channel(raw[rstart:rend])
                        summary.channels[channel.id] = channel
                    elif rop == OP_MESSAGE:
                        cid, _, stamp, _ = _MESSAGE.unpack_from(raw, rstart)
                        index[cid].append((stamp, rstart - 9))
                        summary.add_message(cid, stamp)
                kept.append(
                    (
                        start - 9,
                        end,
                        index,
                        _ChunkRef(start - 9, cstart, cend, compression, compressed, size),
                    )
                )
        except (struct.error, UnicodeDecodeError):
            break
        good_end = end
    if backup is not None:
        shutil.move(path, backup)
    temp = output.with_name(f".{output.name}.reindex")
    try:
        with temp.open("wb") as out:
            out.write(data[:data_start])
            for start, end, chunk_index, ref in kept:
                pos = out.tell()
                out.write(data[start:end])
                if chunk_index is not None and ref is not None:
                    length = out.tell() - pos
                    offsets, index_len = _message_indexes(out, chunk_index)
                    summary.chunk_indexes.append(
                        _chunk_index(
                            ref.start,
                            ref.end,
                            pos,
                            length,
                            offsets,
                            index_len,
                            ref.compression,
                            ref.compressed,
                            ref.uncompressed,
                        )
                    )
            summary.write(out)
        temp.replace(output)
    except OSError as err:
        temp.unlink(missing_ok=True)
        if backup is not None and not path.exists():
            shutil.move(backup, path)
        msg = f"cannot write {output}: {err.strerror or err}"
        raise BagError(msg) from None
    return sum(summary.counts.values()), len(data) - good_end
