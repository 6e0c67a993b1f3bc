"""A bag file as untrusted input: every length and offset it declares is checked before it
is used, and what cannot be read is one error or warning naming the file and the place.

- :class:`BagInput`: the file (a regular file only, see :func:`belvedere.bounded.open_regular`),
  its size, and reads of declared lengths at declared offsets, each checked against the end
  of the file and against :data:`RECORD_BYTES`.
- :class:`Damaged`: raised by the parsers when a record is not what it declares; the reader
  turns it into a located :class:`BagError` (``x.bag: offset 4117: …``) or, for one chunk
  among many, a warning.
- :class:`Skipped`: the damaged chunks a reader skipped — the first one warned about, the
  others counted and summed up when the bag is closed.
- :func:`inflate_chunk`: a chunk's data, inflated to exactly its declared size.
- :func:`replace_with`: a repair written in place of the bag, the original kept.
"""

from __future__ import annotations

import logging
import os
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO, Final, NamedTuple

from belvedere.bags._model import BagError
from belvedere.bounded import (
    DATA_FILE_BYTES,
    INFLATED_BYTES,
    LimitError,
    describe_size,
    inflate,
    open_regular,
)

__all__ = [
    "RECORD_BYTES",
    "BagInput",
    "Damaged",
    "Repaired",
    "Skipped",
    "inflate_chunk",
    "replace_with",
]

logger = logging.getLogger("belvedere.bags")

RECORD_BYTES: Final = INFLATED_BYTES
"""What one record of a bag may declare it holds (a chunk's compressed data, its inflated
data, a message, a record header): the cap on what reading one record allocates."""


class Damaged(Exception):  # noqa: N818 (not an error the user sees: the reader words that)
    """A record that is not what it declares: ``at`` is where, in the buffer parsed;
    ``truncated``: it runs past the end of the file (as a recording cut short leaves it)."""

    def __init__(self, at: int, text: str, *, truncated: bool = False) -> None:
        super().__init__(text)
        self.at = at
        self.text = text
        self.truncated = truncated


class BagInput:
    """A bag file open for reading, and located errors about it."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.f = open_regular(path, limit=DATA_FILE_BYTES, what="bag")
        self.size = os.fstat(self.f.fileno()).st_size

    def error(self, pos: int, text: str, *, hint: str | None = None) -> BagError:
        """``{path}: offset {pos}: {text}``."""
        return BagError(f"{self.path}: offset {pos}: {text}", hint=hint)

    def check(self, pos: int, length: int, what: str, *, end: int | None = None) -> None:
        """Raise :class:`Damaged` (at ``pos``) unless ``length`` bytes from ``pos`` are in the
        file (before ``end``, if given) and within :data:`RECORD_BYTES`."""
        limit = self.size if end is None else end
        if pos + length > limit:
            past = "the end of the file" if end is None else "where its section ends"
            text = f"{what} of {length:,} bytes runs past {past} (at offset {limit:,})"
            raise Damaged(pos, text, truncated=end is None)
        if length > RECORD_BYTES:
            text = (
                f"{what} declares {length:,} bytes, more than the "
                f"{describe_size(RECORD_BYTES)} belvedere reads as one record"
            )
            raise Damaged(pos, text)

    def read(self, pos: int, length: int, what: str, *, end: int | None = None) -> bytes:
        """Exactly ``length`` bytes at ``pos`` (checked as :meth:`check`)."""
        self.check(pos, length, what, end=end)
        self.f.seek(pos)
        data = self.f.read(length)
        if len(data) != length:  # the file shrank while being read
            text = f"{what} of {length:,} bytes is cut short at offset {pos + len(data):,}"
            raise Damaged(pos, text)
        return data

    def close(self) -> None:
        self.f.close()


class Skipped:
    """Damaged chunks a reader skipped: each place once, the first warned about at once, the
    others summed up by :meth:`summary`."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.places: dict[int, str] = {}

    def skip(self, chunk: int, at: int, text: str) -> None:
        """The chunk at offset ``chunk`` cannot be read (all or part): ``text`` says why and
        ``at`` where (a file offset)."""
        if chunk in self.places:
            return  # read again (play --loop): said already
        self.places[chunk] = text
        if len(self.places) == 1:
            logger.warning("%s: offset %d: %s", self.path, at, text)

    def summary(self) -> None:
        """Warn how many chunks were skipped in all, when more than the one already named."""
        if len(self.places) > 1:
            logger.warning(
                "%s: %d damaged chunks skipped in all (the first is named above; offsets %s)",
                self.path,
                len(self.places),
                _offsets(sorted(self.places)),
            )


def _offsets(places: list[int]) -> str:
    shown = ", ".join(str(p) for p in places[:5])
    return shown + (f" and {len(places) - 5} more" if len(places) > 5 else "")


def inflate_chunk(
    compression: str, codecs: dict[str, str], data: bytes, size: int, at: int
) -> bytes:
    """A chunk's ``data``, inflated to exactly its declared ``size``: ``codecs`` maps the
    format's names of compressions to :func:`belvedere.bounded.inflate`'s ('': none).

    Raises:
        Damaged: (at ``at``) an unknown compression, damaged data, or another size than
            declared — a bomb stops at the declared size.
    """
    codec = codecs.get(compression)
    if codec is None:
        known = ", ".join(repr(name) for name in codecs)
        raise Damaged(at, f"chunk: unknown compression {compression!r} (known: {known})")
    if not codec:
        if len(data) != size:
            text = f"chunk: holds {len(data):,} bytes, not the {size:,} it declares"
            raise Damaged(at, text)
        return data
    try:
        return inflate(codec, data, size=size, where="chunk", cap=RECORD_BYTES)
    except LimitError as err:
        raise Damaged(at, err.message) from None


class Repaired(NamedTuple):
    """What a repair (``bag reindex``) kept."""

    output: Path
    messages: int
    dropped: int
    """Bytes of the source after what was kept (not counting an index or summary)."""
    damage: str | None
    """Why the repair stopped before the end of the source (``x.bag: offset N: …``), when
    that was damage rather than the end of a recording cut short."""


def replace_with(
    inp: BagInput, output: Path, backup: Path | None, write: Callable[[BinaryIO], int]
) -> int:
    """Write ``output`` with ``write`` (through a temporary file beside it); when ``backup``
    is given, the source (``inp``, which may be ``output``) is moved there first — it is
    read on through the open file. Returns what ``write`` returns.

    Raises:
        BagError: ``output`` cannot be written (or the source changed while being read);
            the source is put back.
    """
    path = inp.path
    if backup is not None:
        shutil.move(path, backup)
    temp = output.with_name(f".{output.name}.reindex")
    try:
        with temp.open("wb") as target:
            result = write(target)
        temp.replace(output)
    except BaseException as err:
        temp.unlink(missing_ok=True)
        if backup is not None and not path.exists():
            shutil.move(backup, path)
        if isinstance(err, OSError):
            msg = f"cannot write {output}: {err.strerror or err}"
            raise BagError(msg) from None
        if isinstance(err, Damaged):  # the source changed since it was read
            raise inp.error(err.at, err.text) from None
        raise
    return result
