"""Byte-level mutations of binary files, as hypothesis strategies (so a failure shrinks to
one edit).

A mutation is a short list of edits, each drawn as plain integers that index into the file
it meets: flip a bit, overwrite a length field with a lie (at one of the file's own length
fields, which the caller lists, or anywhere), truncate, delete or duplicate a span, or
splice in a span of another file. The lies are the numbers that break readers: 0, 1, just
past the end, 2^31, 2^32 - 16, 2^33, 2^63.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Final

from hypothesis import strategies as st

from tests.fuzz._mutate import Mutation

__all__ = ["LIES", "ByteEdit", "byte_edits", "byte_mutant"]

LIES: Final = (
    0,
    1,
    7,
    22,
    0x7F,
    0xFFFF,
    1 << 20,
    0x7FFFFFFF,
    0x80000000,
    0xFFFFFFF0,
    0xFFFFFFFF,
    1 << 33,
    1 << 62,
    1 << 63,
    (1 << 64) - 1,
)
"""Numbers a length or offset field may lie with (cut to the field's width)."""

KINDS: Final = ("flip", "lie", "lie-anywhere", "truncate", "delete", "duplicate", "splice")


ByteEdit = Mutation
"""A byte edit is drawn as a tree or text edit is; only its kinds (:data:`KINDS`) differ."""


def byte_edits(*, max_edits: int = 3) -> st.SearchStrategy[list[ByteEdit]]:
    """Lists of byte edits."""
    number = st.integers(0, 2**20)
    edit = st.builds(ByteEdit, st.sampled_from(KINDS), number, number, number)
    return st.lists(edit, min_size=1, max_size=max_edits)


def byte_mutant(
    data: bytes,
    edits: Sequence[ByteEdit],
    fields: Sequence[tuple[int, int]] = (),
    donors: Sequence[bytes] = (),
) -> bytes:
    """``data`` with ``edits`` applied in turn. ``fields`` are (offset, width) of its length
    and offset fields, where ``lie`` writes; ``donors`` other files ``splice`` takes from.

    Each edit applies to the file as the edits before it left it (a field past its end is
    not written)."""
    out = bytearray(data)
    for edit in edits:
        n = len(out)
        if edit.kind == "flip" and n:
            out[edit.a % n] ^= 1 << (edit.b % 8)
        elif edit.kind == "lie" and fields:
            at, width = fields[edit.a % len(fields)]
            _write(out, at, width, LIES[edit.b % len(LIES)], edit.c)
        elif edit.kind == "lie-anywhere" and n:
            _write(out, edit.a % n, 4 if edit.c % 2 else 8, LIES[edit.b % len(LIES)], edit.c)
        elif edit.kind == "truncate":
            del out[edit.a % (n + 1) :]
        elif edit.kind == "delete" and n:
            at = edit.a % n
            del out[at : at + 1 + edit.b % 64]
        elif edit.kind == "duplicate" and n:
            at = edit.a % n
            out[at:at] = out[at : at + 1 + edit.b % 512]
        elif edit.kind == "splice" and donors:
            donor = donors[edit.c % len(donors)]
            start = edit.b % max(1, len(donor))
            out[edit.a % (n + 1) : edit.a % (n + 1)] = donor[start : start + 1 + edit.c % 1024]
    return bytes(out)


def _write(out: bytearray, at: int, width: int, value: int, nudge: int) -> None:
    """``value`` (or, for one ``nudge`` in three, the field's own value off by a little) written
    little-endian in ``width`` bytes at ``at``."""
    if at + width > len(out):
        return
    if nudge % 3 == 1:  # off by a little: the lies a careless writer tells
        value = int.from_bytes(out[at : at + width], "little") + (nudge % 17) - 8
    out[at : at + width] = (value % (1 << (8 * width))).to_bytes(width, "little")
