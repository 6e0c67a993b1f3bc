"""Opening bags of either format, writing them, and repairing them."""

from __future__ import annotations

import heapq
import os
from collections.abc import Collection, Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any, Protocol

from belvedere.bags._mcap import MAGIC as MCAP_MAGIC
from belvedere.bags._mcap import McapWriter
from belvedere.bags._mcap_read import McapBag
from belvedere.bags._mcap_recover import recover_mcap
from belvedere.bags._model import BagError, BagMessage, Connection
from belvedere.bags._ros1 import MAGIC as ROS1_MAGIC
from belvedere.bags._ros1 import ChunkStats, Ros1Bag, Ros1BagWriter
from belvedere.bags._ros1_repair import reindex_ros1

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
    ) -> Iterator[BagMessage]: ...
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


def _kind(path: Path) -> str:
    """``bag`` or ``mcap``, from the file's first bytes."""
    try:
        with path.open("rb") as f:
            head = f.read(len(ROS1_MAGIC))
    except IsADirectoryError:
        msg = f"{path} is a directory, not a bag"
        raise BagError(msg) from None
    except FileNotFoundError:
        msg = f"no such bag: {path}"
        raise BagError(msg) from None
    except OSError as err:
        msg = f"cannot read {path}: {err.strerror or err}"
        raise BagError(msg) from None
    if head.startswith(MCAP_MAGIC):
        return "mcap"
    if head.startswith(b"#ROSBAG V"):
        if head != ROS1_MAGIC:
            version = head[len("#ROSBAG V") :].decode(errors="replace").strip()
            msg = f"{path} is a ROS 1 bag of format {version}; belvedere reads 2.0"
            raise BagError(msg, hint="rosbag fix or rosbag reindex in ROS 1 converts old bags")
        return "bag"
    if not head:
        msg = f"{path} is empty"
        raise BagError(msg)
    msg = f"{path} is neither a ROS 1 bag nor an MCAP file"
    raise BagError(msg)


def open_bag(path: str | os.PathLike[str]) -> BagFile:
    """A bag open for reading, whichever its format."""
    p = Path(path)
    if _kind(p) == "mcap":
        return McapBag(p)
    return Ros1Bag(p)


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


def reindex(
    path: Path, *, output_dir: Path | None = None, force: bool = False
) -> tuple[Path, int, int]:
    """Repair a bag whose recording was cut short, as ``rosbag reindex``: the original is
    kept as ``x.orig.bag`` (or the result goes to ``output_dir``). MCAP files get a new
    summary. Returns (repaired file, messages it holds, bytes dropped from its end)."""
    kind = _kind(path)
    if output_dir is not None:
        output, backup = output_dir / path.name, None
        if output.resolve() == path.resolve():
            output, backup = path, backup_path(path)
    else:
        output, backup = path, backup_path(path)
    if backup is not None and backup.exists() and not force:
        msg = f"skipping {path}: the backup {backup} exists already"
        raise BagError(msg, hint="remove it, or use --force to overwrite it")
    if kind == "mcap":
        messages, dropped = recover_mcap(path, output, backup)
    else:
        messages, dropped = reindex_ros1(path, output, backup)
    return output, messages, dropped
