"""Recovering MCAP files whose recording was cut short (see :mod:`belvedere.bags._mcap`):
the data section read record by record, up to its end or the first record that is cut
short or damaged, and written again with its message indexes and a new summary."""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from belvedere.bags._input import BagInput, Damaged, Repaired, replace_with
from belvedere.bags._mcap import (
    _MESSAGE,
    _RECORD,
    OP_CHANNEL,
    OP_CHUNK,
    OP_DATA_END,
    OP_FOOTER,
    OP_HEADER,
    OP_MESSAGE,
    OP_SCHEMA,
    _chunk_index,
    _ChunkRef,
    _fixed,
    _inflated_chunk,
    _message_head,
    _message_indexes,
    _parse_channel,
    _parse_schema,
    _records,
    _Summary,
)
from belvedere.bags._model import BagError

__all__ = ["recover_mcap"]

_LAST_KNOWN_OP = 0x0F
"""The spec's records go from 0x01 up to DataEnd (0x0F): past it (or at 0x00), a record is
not one."""


@dataclass
class _Kept:
    """A record the recovery keeps: where it is in the source; a chunk's message index."""

    start: int
    end: int
    index: dict[int, list[tuple[int, int]]] | None = None
    ref: _ChunkRef | None = None


def recover_mcap(inp: BagInput, output: Path, backup: Path | None) -> Repaired:
    """Write the whole chunks (and loose records) of the MCAP file ``inp`` to ``output``
    with a new summary (``output`` may be its path: the original is moved to ``backup``
    first, and kept).

    Raises:
        BagError: its header is damaged, or no message comes before the first damaged or
            cut-short record (``x.mcap: offset N: …``); the file is left as it was.
    """
    path = inp.path
    try:
        op, length = _RECORD.unpack(inp.read(8, 9, "the header record"))
        if op != OP_HEADER:
            raise Damaged(8, "no header record after the magic")
        inp.check(17, length, "the header record")
    except Damaged as err:
        raise inp.error(err.at, err.text) from None
    data_start = 17 + length
    summary = _Summary()
    kept: list[_Kept] = []
    pos = data_start
    damage = None
    clean = False
    while pos < inp.size:
        try:
            op, length = _RECORD.unpack(inp.read(pos, 9, "a record"))
            body = pos + 9
            inp.check(body, length, "a record")
            if op in (OP_DATA_END, OP_FOOTER):
                clean = True
                break
            if not op or op > _LAST_KNOWN_OP:
                raise Damaged(pos, f"a record of unknown kind {op:#04x}")
            item = _record(inp, op, pos, length, summary)
            if item is not None:
                kept.append(item)
        except Damaged as err:
            damage = err
            break
        pos = body + length
    count = sum(summary.counts.values())
    if damage is not None and not count:
        msg = f"{path}: offset {damage.at}: {damage.text}: no message before it to keep"
        raise BagError(msg)

    def write(out: BinaryIO) -> int:
        out.write(inp.read(0, data_start, "the header"))
        for item in kept:
            at = out.tell()
            out.write(inp.read(item.start, item.end - item.start, "a record"))
            ref = item.ref
            if item.index is not None and ref is not None:
                length = out.tell() - at
                offsets, index_len = _message_indexes(out, item.index)
                summary.chunk_indexes.append(
                    _chunk_index(
                        ref.start,
                        ref.end,
                        at,
                        length,
                        offsets,
                        index_len,
                        ref.compression,
                        ref.compressed,
                        ref.uncompressed,
                    )
                )
        summary.write(out)
        return count

    replace_with(inp, output, backup, write)
    dropped = 0 if clean else inp.size - pos
    reason = None
    if damage is not None and not damage.truncated:
        reason = f"{path}: offset {damage.at}: {damage.text}"
    return Repaired(output, count, dropped, reason)


def _record(inp: BagInput, op: int, pos: int, length: int, summary: _Summary) -> _Kept | None:
    """The record at ``pos`` added to ``summary``; what to keep of it (None: nothing — the
    indexes and the summary are written again).

    Raises:
        Damaged: it is not what it declares.
    """
    body = pos + 9
    end = body + length
    if op == OP_SCHEMA:
        schema = _parse_schema(inp.read(body, length, "a schema record"), body)
        summary.schemas[schema.id] = schema
    elif op == OP_CHANNEL:
        channel = _parse_channel(inp.read(body, length, "a channel record"), body)
        summary.channels[channel.id] = channel
    elif op == OP_MESSAGE:
        summary.add_message(*_message_head(inp, body, length))
    elif op == OP_CHUNK:
        return _chunk(inp, pos, length, summary)
    else:
        return None
    return _Kept(pos, end)


def _chunk(inp: BagInput, pos: int, length: int, summary: _Summary) -> _Kept:
    """A chunk record: its messages indexed, its schemas and channels added."""
    ref, raw = _inflated_chunk(inp.read(pos + 9, length, "a chunk record"), pos)
    index: dict[int, list[tuple[int, int]]] = defaultdict(list)
    schemas, channels, found = [], [], []
    try:
        for rop, rstart, rend in _records(raw, 0):
            record = raw[rstart:rend]
            if rop == OP_SCHEMA:
                schemas.append(_parse_schema(record, rstart))
            elif rop == OP_CHANNEL:
                channels.append(_parse_channel(record, rstart))
            elif rop == OP_MESSAGE:
                _fixed(record, OP_MESSAGE, "a message", rstart)
                cid, _, stamp, _ = _MESSAGE.unpack_from(record, 0)
                index[cid].append((stamp, rstart - 9))
                found.append((cid, stamp))
    except Damaged as err:
        text = f"chunk, at byte {err.at:,} of its data: {err.text}"
        raise Damaged(pos, text) from None
    # Added once the whole chunk is known good.
    summary.schemas.update((s.id, s) for s in schemas)
    summary.channels.update((c.id, c) for c in channels)
    for cid, stamp in found:
        summary.add_message(cid, stamp)
    return _Kept(pos, pos + 9 + length, index, ref)
