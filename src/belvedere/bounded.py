"""Reading what users hand us within stated bounds: files, compressed data, sizes.

Users open bags, maps, worlds and launch files downloaded from the internet. Every
allocation whose size such a file decides (bytes read, bytes inflated, pixels, grid cells,
beams) is checked here against one of the caps below *before* it is made, and a refusal is
one :class:`LimitError` that names the file, the place and the cap. The README's
*Reliability* section lists these caps; change them here and there together.

- :func:`open_regular` / :func:`read_regular`: a regular file only (a FIFO, a device such as
  ``/dev/zero`` or a directory is refused without blocking), at most ``limit`` bytes.
- :func:`inflate`: a compressed block that must inflate to exactly its declared size, never
  past it, streamed so a bomb stops at the cap.
- :func:`check_count`: a count (pixels, cells, beams, a declared length) against its cap.
"""

from __future__ import annotations

import bz2
import os
import stat
import zlib
from typing import IO, Any, Final

from belvedere.errors import BelvedereError, SourceLocation

__all__ = [
    "COMMAND_OUTPUT_BYTES",
    "COMMAND_SECONDS",
    "DATA_FILE_BYTES",
    "GRID_CELLS",
    "IMAGE_FILE_BYTES",
    "IMAGE_PIXELS",
    "INFLATED_BYTES",
    "POSE_METRES",
    "SCAN_BEAMS",
    "SCRIPT_BYTES",
    "TEXT_FILE_BYTES",
    "LimitError",
    "check_count",
    "describe_size",
    "inflate",
    "open_regular",
    "read_regular",
]

MiB: Final = 1 << 20

TEXT_FILE_BYTES: Final = 64 * MiB
"""A text file read whole: XML (URDF, xacro, SDF, launch), YAML, .rviz, a PGM's header."""
IMAGE_FILE_BYTES: Final = 512 * MiB
"""An image file (map, texture) read to be decoded."""
IMAGE_PIXELS: Final = 1 << 26
"""Pixels of one decoded image (a map or a texture): 67,108,864, 8192 x 8192 — an 8K texture,
or a 410 m square map at 5 cm. Pillow's own guard warns at 89 Mpx and stops only at 179."""
INFLATED_BYTES: Final = 512 * MiB
"""What one compressed block (a bag's or MCAP file's chunk) may declare it inflates to;
rosbag writes 768 KiB chunks and MCAP writers a few MiB."""
DATA_FILE_BYTES: Final = 1 << 40
"""A bag or MCAP file is streamed, not read whole: only its records are bounded (by
:data:`INFLATED_BYTES` and the file's own size)."""
GRID_CELLS: Final = 1 << 25
"""Cells of one grid sized by input (a SLAM map, a costmap, amcl's likelihood field):
33,554,432, a 290 m square at 5 cm. A grid that would grow past it is refused, and the
reading that asked for it skipped."""
SCAN_BEAMS: Final = 1 << 16
"""Beams of one laser scan (65,536; real 2D lidars have 360 to 3,600)."""
POSE_METRES: Final = 1e8
"""A pose read from input (odometry, a sensor's mount, an initial pose) with a coordinate
farther than this from its frame's origin is refused: 100,000 km, past any robot's odometry
(UTM coordinates reach 1e7 m) — a jump there is a broken reading, not a motion."""
COMMAND_OUTPUT_BYTES: Final = 64 * MiB
"""What one ``<param command="…">`` (or ``$(eval …)`` command) may print, stdout and stderr
each."""
COMMAND_SECONDS: Final = 120.0
"""How long such a command may run before it is stopped."""
SCRIPT_BYTES: Final = 2 * MiB
"""A Python 2 script translated to Python 3 (course scripts are a few KiB)."""


class LimitError(BelvedereError):
    """An input that is not a readable file of a sane size, or asks for more than a cap."""

    def __init__(
        self, message: str, location: SourceLocation | None = None, *, hint: str | None = None
    ) -> None:
        super().__init__(message, hint=hint)
        self.location = location

    def describe(self) -> str:
        head = f"{self.location}: error: " if self.location else "error: "
        text = head + self.message
        if self.hint:
            text += f"\n  hint: {self.hint}"
        return text


def describe_size(n: int) -> str:
    """``1.5 GiB``, ``64 MiB``, ``812 bytes``: a size as people read it."""
    for unit, scale in (("GiB", 1 << 30), ("MiB", MiB), ("KiB", 1 << 10)):
        if n >= scale:
            value = n / scale
            return f"{value:.0f} {unit}" if value == int(value) else f"{value:.1f} {unit}"
    return f"{n} bytes"


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def open_regular(
    path: str | os.PathLike[str],
    *,
    limit: int = TEXT_FILE_BYTES,
    what: str = "file",
    at: SourceLocation | None = None,
) -> IO[bytes]:
    """``path`` opened for reading in binary, if it is a regular file of at most ``limit``
    bytes (after following symlinks).

    The file is opened without blocking first, so a FIFO with no writer is refused rather than
    waited for. ``what`` names it in errors (``map image``); ``at`` is where it was asked for.

    Raises:
        LimitError: it cannot be opened, is not a regular file, or is larger than ``limit``.
    """
    shown = os.fspath(path)
    try:
        fd = os.open(shown, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError as err:
        msg = f"cannot read {what} {shown}: {err.strerror or err}"
        raise LimitError(msg, at) from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            msg = f"cannot read {what} {shown}: it is {_kind(info.st_mode)}, not a regular file"
            raise LimitError(msg, at)
        if info.st_size > limit:
            msg = (
                f"cannot read {what} {shown}: it is {describe_size(info.st_size)}, "
                f"more than the {describe_size(limit)} belvedere reads"
            )
            raise LimitError(msg, at)
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_regular(
    path: str | os.PathLike[str],
    *,
    limit: int = TEXT_FILE_BYTES,
    what: str = "file",
    at: SourceLocation | None = None,
) -> bytes:
    """The bytes of ``path`` (see :func:`open_regular`); a file that grows past ``limit``
    while being read is refused too."""
    with open_regular(path, limit=limit, what=what, at=at) as f:
        try:
            data = f.read(limit + 1)
        except OSError as err:
            msg = f"cannot read {what} {os.fspath(path)}: {err.strerror or err}"
            raise LimitError(msg, at) from None
    if len(data) > limit:
        msg = f"cannot read {what} {os.fspath(path)}: it grew past {describe_size(limit)}"
        raise LimitError(msg, at)
    return data


def check_count(
    count: int, cap: int, what: str, *, where: str = "", at: SourceLocation | None = None
) -> int:
    """``count`` if it is at most ``cap``; else one :class:`LimitError`:
    ``{where}: {what}: 5,000,000 is more than the cap of 65,536``."""
    if count <= cap:
        return count
    prefix = f"{where}: " if where else ""
    msg = f"{prefix}{what}: {count:,} is more than the cap of {cap:,}"
    raise LimitError(msg, at)


class _Inflater:
    """One codec's streaming decompressor, behind one ``decompress(data, max_length)``."""

    def __init__(self, codec: str) -> None:
        self.codec = codec
        self._impl: Any
        if codec == "bz2":
            self._impl = bz2.BZ2Decompressor()
        elif codec == "lz4":
            import lz4.frame

            self._impl = lz4.frame.LZ4FrameDecompressor()
        elif codec == "zstd":
            self._impl = _zstd().ZstdDecompressor()
        elif codec in ("gzip", "zlib"):
            self._impl = zlib.decompressobj(wbits=47)  # zlib or gzip header, detected
        else:
            msg = f"unknown compression {codec!r} (known: bz2, lz4, zstd, gzip)"
            raise LimitError(msg)

    def decompress(self, data: bytes, max_length: int) -> bytes:
        if self.codec in ("gzip", "zlib"):
            out: bytes = self._impl.decompress(data, max_length)
            return out
        return bytes(self._impl.decompress(data, max_length=max_length))


def _zstd() -> Any:
    try:
        from compression import zstd  # type: ignore[import-not-found]  # Python 3.14
    except ImportError:
        try:
            from backports import zstd
        except ImportError:
            msg = "zstd-compressed data needs the backports.zstd package"
            raise LimitError(msg, hint="pip install backports.zstd") from None
    return zstd


def inflate(codec: str, data: bytes, *, size: int, where: str, cap: int = INFLATED_BYTES) -> bytes:
    """``data`` decompressed with ``codec`` (``bz2``, ``lz4`` frame, ``zstd``, ``gzip``),
    which must give exactly ``size`` bytes, the size its container declares.

    Never holds more than ``size`` + 1 bytes of output: a block that inflates past its
    declared size is refused as soon as it does (a bomb stops there).

    Raises:
        LimitError: ``where: …`` — the declared size is past ``cap``, the data is not valid
            ``codec`` data, or it inflates to another size than declared.
    """
    if size < 0 or size > cap:
        msg = (
            f"{where}: declares {size:,} bytes uncompressed, "
            f"more than the {describe_size(cap)} belvedere inflates"
            if size > cap
            else f"{where}: declares a negative uncompressed size ({size})"
        )
        raise LimitError(msg)
    inflater = _Inflater(codec)
    try:
        out = inflater.decompress(data, size + 1)
    except Exception as err:  # noqa: BLE001 (each codec raises its own kinds on bad data)
        msg = f"{where}: damaged {codec} data ({_reason(err)})"
        raise LimitError(msg) from None
    if len(out) > size:
        msg = f"{where}: inflates past its declared {size:,} bytes"
        raise LimitError(msg)
    if len(out) < size:
        msg = f"{where}: inflates to {len(out):,} bytes, not the {size:,} it declares"
        raise LimitError(msg)
    return out


def _reason(err: BaseException) -> str:
    text = str(err).strip() or type(err).__name__
    return text if len(text) <= 120 else text[:117] + "..."
