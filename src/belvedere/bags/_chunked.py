"""What reading and writing a ROS 1 bag and an MCAP file share: both keep messages in
chunks, each written when it is full or flushed and read when the merge in time order
reaches it.

- :class:`ChunkedBag`: a reader's common face — opening (damage turned into one located
  error, the file closed), the messages of the wanted connections merged chunk by chunk, a
  damaged chunk skipped with a warning, closing.
- :class:`ChunkWriter`: a writer's file, its open chunk (buffer, message index, time span),
  its size and flushing.
"""

from __future__ import annotations

import heapq
from abc import ABC, abstractmethod
from collections import defaultdict
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import BinaryIO

from belvedere.bags._input import BagInput, Damaged, Skipped
from belvedere.bags._model import BagError, BagMessage, Connection

__all__ = ["ChunkParser", "ChunkWriter", "ChunkedBag", "Timed"]

Timed = tuple[int, BagMessage | None]
"""A message and its time for the merge; None: a chunk not read yet, placed at its start."""

ChunkParser = Callable[[bytes, dict[int, Connection], int, int, list[BagMessage]], None]
"""Adds the messages of a chunk's inflated data on the connections in [lo, hi) to a list;
raises :class:`Damaged` at a byte of that data, the messages before it added."""


class ChunkedBag(ABC):
    """A bag open for reading: a subclass reads its format's header and index in
    :meth:`_open` and lists its chunks' messages in :meth:`_sources`.

    Raises:
        BagError: what :meth:`_open` raises, or its :class:`Damaged` located in the file
            (``x.bag: offset N: …``) with :attr:`_hint`.
    """

    def __init__(self, inp: BagInput) -> None:
        self.path = inp.path
        self._in = inp
        self.skipped = Skipped(inp.path)
        self._hint: str | None = None
        """How to repair the file, once it is known to be whole enough to repair."""

    def _opened(self) -> None:
        """:meth:`_open`, the file closed when it fails."""
        inp = self._in
        try:
            self._open()
        except Damaged as err:
            inp.close()
            raise inp.error(err.at, err.text, hint=self._hint) from None
        except BaseException:
            inp.close()
            raise

    @abstractmethod
    def _open(self) -> None: ...

    @abstractmethod
    def _by_id(self) -> dict[int, Connection]:
        """Every connection, by id."""

    @abstractmethod
    def _sources(self, conns: dict[int, Connection], lo: int, hi: int) -> list[Iterator[Timed]]:
        """The messages on ``conns`` in [lo, hi), in time order within each source."""

    @property
    def size(self) -> int:
        return self._in.size

    def messages(
        self,
        connections: Iterable[Connection] | None = None,
        start_ns: int | None = None,
        stop_ns: int | None = None,
    ) -> Iterator[BagMessage]:
        conns = self._by_id()
        if connections is not None:
            wanted = {c.id for c in connections}
            conns = {k: v for k, v in conns.items() if k in wanted}
        if not conns:
            return
        lo = 0 if start_ns is None else start_ns
        hi = 2**64 if stop_ns is None else stop_ns
        for item in heapq.merge(*self._sources(conns, lo, hi), key=lambda m: m[0]):
            if item[1] is not None:
                yield item[1]

    def _chunk_messages(
        self,
        pos: int,
        start: int,
        inflated: Callable[[], bytes],
        parse: ChunkParser,
        conns: dict[int, Connection],
        lo: int,
        hi: int,
    ) -> Iterator[Timed]:
        """The messages of the chunk at ``pos`` (its first at ``start``), its data from
        ``inflated`` read only when the merge reaches it."""
        yield start, None
        found: list[BagMessage] = []
        try:
            raw = inflated()
        except Damaged as err:
            self.skipped.skip(pos, err.at, f"{err.text}; skipping its messages")
        else:
            try:
                parse(raw, conns, lo, hi, found)
            except Damaged as err:
                text = f"chunk, at byte {err.at:,} of its data: {err.text}; skipping the rest"
                self.skipped.skip(pos, pos, text)
        found.sort(key=lambda m: m.stamp_ns)
        for message in found:
            yield message.stamp_ns, message

    def close(self) -> None:
        self._in.close()
        self.skipped.summary()


def create(path: Path) -> BinaryIO:
    """``path`` open for writing a bag.

    Raises:
        BagError: it cannot be.
    """
    try:
        return path.open("wb")
    except OSError as err:
        msg = f"cannot write {path}: {err.strerror or err}"
        raise BagError(msg) from None


class ChunkWriter(ABC):
    """A bag being written: the file, and the chunk open in memory until :meth:`_write_chunk`
    writes it (when it is full, flushed or closed)."""

    def __init__(self, path: Path, chunk_size: int) -> None:
        self.path = path
        self._f = create(path)
        self._chunk_size = chunk_size
        self._new_chunk()

    def _new_chunk(self) -> None:
        self._buf = bytearray()
        self._index: dict[int, list[tuple[int, int]]] = defaultdict(list)
        """Per connection, (time, offset in the chunk) of each message."""
        self._start = 2**64 - 1
        self._end = 0

    def _indexed(self, connection: int, stamp_ns: int) -> None:
        """A message on ``connection`` at ``stamp_ns`` starts at the end of the chunk."""
        self._index[connection].append((stamp_ns, len(self._buf)))
        self._start = min(self._start, stamp_ns)
        self._end = max(self._end, stamp_ns)

    @abstractmethod
    def _write_chunk(self) -> None:
        """Write the open chunk, if it holds messages, and open another."""

    @property
    def size(self) -> int:
        """Bytes so far, the open chunk's too."""
        return self._f.tell() + len(self._buf)

    def flush(self) -> None:
        """Write the open chunk (if it holds messages) and hand the file to the system."""
        self._write_chunk()
        self._f.flush()
