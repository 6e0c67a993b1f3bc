"""Reading what users hand us within stated bounds: files, compressed data, sizes.

Users open bags, maps, worlds and launch files downloaded from the internet. Every
allocation whose size such a file decides (bytes read, bytes inflated, pixels, grid cells,
beams) is checked here against one of the caps below *before* it is made, and a refusal is
one :class:`LimitError` that names the file, the place and the cap. The caps
table of ``docs/reliability.md`` lists them; change them here and there together.

- :func:`open_regular` / :func:`read_regular` / :func:`read_regular_text`: a regular file
  only (a FIFO, a device such as ``/dev/zero`` or a directory is refused without blocking),
  at most ``limit`` bytes.
- :func:`inflate`: a compressed block that must inflate to exactly its declared size, never
  past it, streamed so a bomb stops at the cap.
- :func:`check_count`: a count (pixels, cells, beams, a declared length) against its cap.
- :func:`check_pixels`: an image's size, read from its header, against :data:`IMAGE_PIXELS`
  before it is decoded.
- :func:`run_bounded`: a program whose output is read as it comes, within a size and a time,
  and killed (with what it started) past either.
"""

from __future__ import annotations

import bz2
import contextlib
import math
import os
import selectors
import signal
import stat
import subprocess
import time
import zlib
from collections.abc import Sequence
from dataclasses import dataclass
from typing import IO, Any, Final

from belvedere.errors import BelvedereError, SourceLocation

__all__ = [
    "COMMAND_OUTPUT_BYTES",
    "COMMAND_SECONDS",
    "DATA_FILE_BYTES",
    "DEFINITION_BYTES",
    "GRID_CELLS",
    "IMAGE_FILE_BYTES",
    "IMAGE_PIXELS",
    "INFLATED_BYTES",
    "MESH_FILE_BYTES",
    "POSE_METRES",
    "SCAN_BEAMS",
    "SCRIPT_BYTES",
    "SCRIPT_SECONDS",
    "TEXT_FILE_BYTES",
    "YAML_TEXT_BYTES",
    "LimitError",
    "Ran",
    "check_count",
    "check_pixels",
    "describe_size",
    "inflate",
    "open_regular",
    "read_regular",
    "read_regular_text",
    "run_bounded",
]

MiB: Final = 1 << 20

TEXT_FILE_BYTES: Final = 64 * MiB
"""A text file read whole: XML (URDF, xacro, SDF, launch), YAML, .rviz, a PGM's header."""
YAML_TEXT_BYTES: Final = 4 * MiB
"""One YAML document (a rosparam file, an rviz config, a map's YAML, a ``type="yaml"`` value):
PyYAML's pure-Python loader, which keeps the lines belvedere reports, reads about 250 KiB/s
and holds about 100 bytes per byte of text, so 4 MiB is some 15 s and 500 MiB. Real ones
are a few KiB."""
IMAGE_FILE_BYTES: Final = 512 * MiB
"""An image file (map, texture) read to be decoded."""
IMAGE_PIXELS: Final = 1 << 26
"""Pixels of one decoded image (a map or a texture): 67,108,864, 8192 x 8192 — an 8K texture,
or a 410 m square map at 5 cm. Pillow's own guard warns at 89 Mpx and stops only at 179."""
MESH_FILE_BYTES: Final = 128 * MiB
"""A mesh file (STL, OBJ, Collada) handed to trimesh: 2.7 million triangles of binary STL,
which trimesh holds in about 1 GiB; robot meshes are a few MiB."""
INFLATED_BYTES: Final = 512 * MiB
"""What one compressed block (a bag's or MCAP file's chunk) may declare it inflates to;
rosbag writes 768 KiB chunks and MCAP writers a few MiB. It also caps what one record of a
bag may declare it holds (belvedere.bags._input.RECORD_BYTES)."""
DATA_FILE_BYTES: Final = 1 << 40
"""A bag or MCAP file is streamed, not read whole: only its records are bounded (by
:data:`INFLATED_BYTES` and the file's own size)."""
DEFINITION_BYTES: Final = 1 * MiB
"""Message definitions one run parses from bags (types the store lacks or lays out
otherwise; a type the store has, with its MD5 sum, is not parsed): the parser takes ~7 s a
MiB, and real definitions are a few KiB each."""
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
COMMAND_SECONDS: Final = 60.0
"""How long such a command may run before it is stopped."""
SCRIPT_BYTES: Final = 512 << 10
"""A script checked (compiled) and translated from Python 2 in process (course scripts are a
few KiB): fissix translates some 60 KiB/s holding ~450 bytes per byte, so 512 KiB is ~9 s
and ~250 MiB (2 MiB, the first choice, was 35 s and 1 GiB). A larger script runs unchecked."""
SCRIPT_SECONDS: Final = 20.0
"""How long translating one script may take: fissix's time grows faster than the script in
some shapes (20,000 adjacent string literals take 11 s), so a byte cap alone bounds no time."""


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


def _label(what: str, name: str) -> str:
    return f"{what} {name}" if what else name


def open_regular(
    path: str | os.PathLike[str],
    *,
    limit: int = TEXT_FILE_BYTES,
    what: str = "file",
    at: SourceLocation | None = None,
    name: str | None = None,
) -> IO[bytes]:
    """``path`` opened for reading in binary, if it is a regular file of at most ``limit``
    bytes (after following symlinks).

    The file is opened without blocking first, so a FIFO with no writer is refused rather than
    waited for. ``what`` names it in errors (``map image``; empty for none); ``name`` is how
    the file is shown there (default: ``path``); ``at`` is where it was asked for. Errors read
    ``cannot read {what} {name}: {why}``.

    Raises:
        LimitError: it cannot be opened, is not a regular file, or is larger than ``limit``.
    """
    shown = _label(what, os.fspath(path) if name is None else name)
    try:
        fd = os.open(os.fspath(path), os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError as err:
        msg = f"cannot read {shown}: {err.strerror or err}"
        raise LimitError(msg, at) from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            msg = f"cannot read {shown}: it is {_kind(info.st_mode)}, not a regular file"
            raise LimitError(msg, at)
        if info.st_size > limit:
            msg = (
                f"cannot read {shown}: it is {describe_size(info.st_size)}, "
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
    name: str | None = None,
) -> bytes:
    """The bytes of ``path`` (see :func:`open_regular`); a file that grows past ``limit``
    while being read is refused too."""
    shown = _label(what, os.fspath(path) if name is None else name)
    with open_regular(path, limit=limit, what=what, at=at, name=name) as f:
        try:
            data = f.read(limit + 1)
        except OSError as err:
            msg = f"cannot read {shown}: {err.strerror or err}"
            raise LimitError(msg, at) from None
    if len(data) > limit:
        msg = f"cannot read {shown}: it grew past {describe_size(limit)}"
        raise LimitError(msg, at)
    return data


def read_regular_text(
    path: str | os.PathLike[str],
    *,
    limit: int = TEXT_FILE_BYTES,
    what: str = "file",
    at: SourceLocation | None = None,
    name: str | None = None,
) -> str:
    """The UTF-8 text of ``path`` (see :func:`open_regular`). Bytes that are not UTF-8 are
    refused at their own line and column (``path:3:7``, the column in bytes)."""
    data = read_regular(path, limit=limit, what=what, at=at, name=name)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        line = data.count(b"\n", 0, err.start) + 1
        col = err.start - (data.rfind(b"\n", 0, err.start) + 1) + 1
        msg = (
            f"cannot read {_label(what, os.fspath(path) if name is None else name)}: "
            f"it is not UTF-8 text (byte 0x{data[err.start]:02x})"
        )
        raise LimitError(msg, SourceLocation(os.fspath(path), line, col)) from None


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


def check_pixels(
    width: int, height: int, *, what: str = "the image", at: SourceLocation | None = None
) -> int:
    """The pixel count of a ``width`` x ``height`` image if it is at most :data:`IMAGE_PIXELS`
    (check it from the header, before decoding); else one :class:`LimitError`:
    ``{what} is 13,000 x 13,000 pixels (169,000,000), more than the 67,108,864
    (8192 x 8192) belvedere decodes``."""
    count = width * height
    if count <= IMAGE_PIXELS:
        return count
    side = math.isqrt(IMAGE_PIXELS)
    msg = (
        f"{what} is {width:,} x {height:,} pixels ({count:,}), more than the "
        f"{IMAGE_PIXELS:,} ({side} x {side}) belvedere decodes"
    )
    raise LimitError(msg, at)


@dataclass(frozen=True)
class Ran:
    """What a program run by :func:`run_bounded` did."""

    status: int | None
    """Its exit status (negative: the signal that ended it); None if it was stopped."""
    stdout: bytes
    stderr: bytes
    stopped: str = ""
    """Why it was stopped: ``""`` (it was not), ``"time"``, ``"stdout"`` or ``"stderr"``
    (the stream that passed the limit). Its output is then empty."""


def run_bounded(argv: Sequence[str], *, seconds: float, limit: int, stdin: bytes = b"") -> Ran:
    """Run ``argv`` with ``stdin`` as its input (``/dev/null`` if empty), reading its stdout
    and stderr as they come: it may print at most ``limit`` bytes on each and run ``seconds``.
    Past either it is killed with whatever it started (it runs in a process group of its
    own), and so it is if the caller is interrupted.

    Raises:
        OSError: it cannot be started.
    """
    process = subprocess.Popen(
        list(argv),
        stdin=subprocess.PIPE if stdin else subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    try:
        return _collect(process, stdin, limit, time.monotonic() + seconds)
    finally:
        _kill(process)


def _collect(process: subprocess.Popen[bytes], stdin: bytes, limit: int, deadline: float) -> Ran:
    """Feed ``stdin`` and read both pipes as they fill until they close and the program
    ends."""
    assert process.stdout is not None
    assert process.stderr is not None
    streams = {
        process.stdout.fileno(): ("stdout", bytearray()),
        process.stderr.fileno(): ("stderr", bytearray()),
    }
    left_to_write = memoryview(stdin)
    with selectors.DefaultSelector() as selector:
        for fd in streams:
            selector.register(fd, selectors.EVENT_READ)
        if process.stdin is not None:
            os.set_blocking(process.stdin.fileno(), False)
            selector.register(process.stdin.fileno(), selectors.EVENT_WRITE)
        while selector.get_map():
            left = deadline - time.monotonic()
            if left <= 0:
                return Ran(None, b"", b"", "time")
            for key, _ in selector.select(left):
                if key.fd not in streams:  # stdin ready for more
                    try:
                        left_to_write = left_to_write[os.write(key.fd, left_to_write[:PIPE_BUF]) :]
                    except BrokenPipeError:  # it stopped reading: what it does is its output
                        left_to_write = left_to_write[:0]
                    if not left_to_write:
                        selector.unregister(key.fd)
                        assert process.stdin is not None
                        process.stdin.close()
                    continue
                chunk = os.read(key.fd, 1 << 16)
                name, got = streams[key.fd]
                if not chunk:
                    selector.unregister(key.fd)
                    continue
                got += chunk
                if len(got) > limit:
                    return Ran(None, b"", b"", name)
    status = _wait(process, deadline)
    if status is None:
        return Ran(None, b"", b"", "time")
    out, err = (bytes(got) for _, got in streams.values())
    return Ran(status, out, err)


def _wait(process: subprocess.Popen[bytes], deadline: float) -> int | None:
    """The program's exit status, or None if it has not ended by ``deadline``: woken by the
    exit itself where Linux gives a pidfd (``Popen.wait`` with a timeout polls, sleeping a
    millisecond and more between looks: a few ms on every command)."""
    try:
        fd = os.pidfd_open(process.pid)
    except (AttributeError, OSError):
        try:
            return process.wait(max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            return None
    try:
        with selectors.DefaultSelector() as selector:
            selector.register(fd, selectors.EVENT_READ)
            if not selector.select(max(0.0, deadline - time.monotonic())):
                return None
    finally:
        os.close(fd)
    return process.wait()


PIPE_BUF: Final = 1 << 16
"""Bytes written to a program's input at a time."""


def _kill(process: subprocess.Popen[bytes]) -> None:
    """End the program and what it started (its process group), if still there; close its
    pipes."""
    if process.returncode is None:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    for pipe in (process.stdin, process.stdout, process.stderr):
        if pipe is not None:
            with contextlib.suppress(OSError):
                pipe.close()


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
