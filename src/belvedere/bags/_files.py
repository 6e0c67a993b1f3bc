"""Opening bags of either format, writing them, and repairing them."""

from __future__ import annotations

import heapq
import os
from collections.abc import Collection, Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any, Protocol

from belvedere.bags._input import BagInput, Repaired, Skipped
from belvedere.bags._mcap import MAGIC as MCAP_MAGIC
from belvedere.bags._mcap import McapWriter
from belvedere.bags._mcap_read import McapBag
from belvedere.bags._mcap_recover import recover_mcap
from belvedere.bags._model import BagError, BagMessage, Connection
from belvedere.bags._ros1 import MAGIC as ROS1_MAGIC
from belvedere.bags._ros1 import ChunkStats, Ros1BagWriter
from belvedere.bags._ros1_read import Ros1Bag
from belvedere.bags._ros1_repair import reindex_ros1
from belvedere.bounded import LimitError

__all__ = [
    "BagFile",
    "BagWriter",
    "backup_path",
    "create_writer",
    "merged_messages",
    "open_bag",
    "reindex",
]


class BagFile(Protocol):
    """A bag open for reading (ROS 1 bag or MCAP)."""

    path: Path
    version: str
    start_ns: int
    """The first message's time."""
    end_ns: int
    """The last message's time."""
    counts: dict[int, int]
    """Messages per connection id."""
    skipped: Skipped
    """The damaged chunks its reading skipped."""

    @property
    def format(self) -> str: ...
    @property
    def connections(self) -> list[Connection]: ...
    @property
    def size(self) -> int: ...
    def chunks(self) -> list[ChunkStats]: ...
    def messages(
        self,
        connections: Iterable[Connection] | None = None,
        start_ns: int | None = None,
        stop_ns: int | None = None,
    ) -> Iterator[BagMessage]:
        """The messages (of ``connections``, in [start, stop)) in time order; a damaged
        chunk is skipped, with a warning (see :attr:`skipped`)."""
        ...

    def close(self) -> None: ...


class BagWriter(Protocol):
    """Writes one bag; connection handles are the format's own."""

    path: Path

    @property
    def encoding(self) -> str: ...
    @property
    def size(self) -> int: ...
    def add_connection(
        self, topic: str, msgtype: str, *, callerid: str | None, latching: bool
    ) -> Any: ...
    def write(self, connection: Any, stamp_ns: int, data: bytes) -> None: ...
    def flush(self) -> None: ...
    def close(self) -> None: ...


def _open(path: Path) -> tuple[BagInput, str]:
    """``path`` open for reading, and its format (``bag`` or ``mcap``) from its first bytes.

    Raises:
        BagError: it is not a regular file, or neither a ROS 1 bag of format 2.0 nor MCAP.
    """
    if not path.exists() and not path.is_symlink():
        msg = f"no such bag: {path}"
        raise BagError(msg)
    try:
        inp = BagInput(path)
    except LimitError as err:
        raise BagError(err.message) from None
    try:
        head = inp.f.read(len(ROS1_MAGIC))
    except OSError as err:
        inp.close()
        msg = f"cannot read {path}: {err.strerror or err}"
        raise BagError(msg) from None
    if head.startswith(MCAP_MAGIC):
        return inp, "mcap"
    if head == ROS1_MAGIC:
        return inp, "bag"
    inp.close()
    if head.startswith(b"#ROSBAG V"):
        version = head[len("#ROSBAG V") :].decode(errors="replace").strip()
        msg = f"{path} is a ROS 1 bag of format {version}; belvedere reads 2.0"
        raise BagError(msg, hint="rosbag fix or rosbag reindex in ROS 1 converts old bags")
    if not head:
        msg = f"{path} is empty"
        raise BagError(msg)
    msg = f"{path} is neither a ROS 1 bag nor an MCAP file"
    raise BagError(msg)


def open_bag(path: str | os.PathLike[str]) -> BagFile:
    """A bag open for reading, whichever its format.

    Raises:
        BagError: it cannot be read (a FIFO, a device or a directory is refused without
            being read), or its header or index is damaged: ``x.bag: offset N: …``.
    """
    inp, kind = _open(Path(path))
    if kind == "mcap":
        return McapBag(inp)
    return Ros1Bag(inp)


def create_writer(
    path: Path, *, compression: str = "none", chunk_size: int | None = None
) -> BagWriter:
    """A writer for ``path``: MCAP when its name ends ``.mcap`` (or ``.mcap.active``),
    else a ROS 1 bag. ``compression``: none, lz4 or bz2 (ROS 1 only)."""
    name = path.name.removesuffix(".active")
    extra = {} if chunk_size is None else {"chunk_size": chunk_size}
    if name.endswith(".mcap"):
        return McapWriter(path, compression=compression, **extra)
    return Ros1BagWriter(path, compression=compression, **extra)


def merged_messages(
    bags: Sequence[BagFile],
    *,
    topics: Collection[str] | None = None,
    start_ns: int | None = None,
    stop_ns: int | None = None,
) -> Iterator[tuple[int, BagMessage]]:
    """(bag index, message) of every bag (only ``topics``' if given), in time order (ties:
    the earlier bag first)."""

    def tagged(i: int, bag: BagFile) -> Iterator[tuple[int, int, BagMessage]]:
        conns = None if topics is None else [c for c in bag.connections if c.topic in topics]
        for m in bag.messages(conns, start_ns, stop_ns):
            yield m.stamp_ns, i, m

    for _, i, m in heapq.merge(*(tagged(i, b) for i, b in enumerate(bags))):
        yield i, m


def backup_path(path: Path) -> Path:
    """rosbag reindex's backup name: ``x.bag`` → ``x.orig.bag``."""
    name = path.name
    base, dot, ext = name.rpartition(".")
    if not dot or not base:
        return path.with_name(name + ".orig")
    return path.with_name(f"{base}.orig.{ext}")


def reindex(path: Path, *, output_dir: Path | None = None, force: bool = False) -> Repaired:
    """Repair a bag whose recording was cut short, as ``rosbag reindex``: every whole chunk
    up to the end of the file (or the first damaged record), with a new index (MCAP: new
    message indexes and summary). The original is kept as ``x.orig.bag`` (or the result
    goes to ``output_dir``, the original untouched).

    Raises:
        BagError: it cannot be read, its backup exists already (unless ``force``), or
            nothing in it can be kept (``x.bag: offset N: …``: the original is untouched).
    """
    if output_dir is not None:
        output, backup = output_dir / path.name, None
        if output.resolve() == path.resolve():
            output, backup = path, backup_path(path)
    else:
        output, backup = path, backup_path(path)
    if backup is not None and backup.exists() and not force:
        msg = f"skipping {path}: the backup {backup} exists already"
        raise BagError(msg, hint="remove it, or use --force to overwrite it")
    inp, kind = _open(path)
    try:
        if kind == "mcap":
            return recover_mcap(inp, output, backup)
        return reindex_ros1(inp, output, backup)
    finally:
        inp.close()
