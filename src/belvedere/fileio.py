"""Writing files so that a user's file is never lost: whole, or not at all.

Every file belvedere writes (``xacro -o``, ``xacro --fix`` and its backups, ``param dump``,
a launch file's ``<rosparam command="dump">``) goes through :func:`write_file` or
:func:`backup_file`:

- the data goes to a temporary file beside the target (``.NAME.belvedere-tmp-XXXXXXXX``),
  is flushed to disk, and is renamed over the target in one step, so a full disk, an
  error or a ``kill -9`` leaves the old file (or none), never a partial one;
- a symlink is followed: the file it points to is replaced, the link stays a link;
- the target's permission bits (and owner, where allowed) are kept; a new file gets the
  permissions any new file gets (``0666`` less the umask), not a temporary file's ``0600``;
- a backup never replaces an existing file: ``FILE.orig`` exists → ``FILE.orig.1`` …;
- the temporary file is removed on every error path. One left by a killed writer is
  removed by the next write to the same target: each writer holds a lock on its temporary
  file, which the kernel drops when the writer dies, so a temporary file nobody holds is
  stale.

Failures raise :class:`FileWriteError`, which names the file and the system's reason
(``cannot write robot.urdf: No space left on device; robot.urdf is unchanged``).
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import logging
import os
import secrets
import stat
from collections.abc import Iterator
from pathlib import Path

from belvedere.errors import BelvedereError

__all__ = [
    "TEMP_MARKER",
    "FileWriteError",
    "StagedWrite",
    "backup_file",
    "stage_backup",
    "stage_write",
    "write_file",
]

logger = logging.getLogger(__name__)

TEMP_MARKER = ".belvedere-tmp-"
"""Part of every temporary file's name: ``.robot.urdf.belvedere-tmp-1a2b3c4d``."""

_NAME_KEEP = 200
"""How much of the target's name a temporary name keeps (names are at most 255 bytes)."""


class FileWriteError(BelvedereError):
    """A file could not be written; what was there before is still there."""

    def __init__(self, path: str | os.PathLike[str], reason: str, *, existed: bool) -> None:
        shown = os.fspath(path)
        after = f"{shown} is unchanged" if existed else "nothing was written"
        super().__init__(f"cannot write {shown}: {reason}; {after}")
        self.path = shown
        self.reason = reason


def _reason(err: OSError) -> str:
    return err.strerror or str(err)


def _temp_prefix(target: Path) -> str:
    return f".{target.name[:_NAME_KEEP]}{TEMP_MARKER}"


class StagedWrite:
    """A file's new content, written in full beside it and not yet in its place.

    :meth:`commit` puts it in place (one rename); :meth:`discard` drops it. Staging several
    files first and committing them after makes a change to several files all or nothing as
    far as disk space and permissions go."""

    def __init__(
        self, shown: str, target: Path, data: bytes, *, backup_of: Path | None = None
    ) -> None:
        self.shown = shown
        """The path as the caller gave it (for messages)."""
        self.target = target
        """The file that will be written: symlinks resolved; for a backup, the name taken."""
        self._backup_of = backup_of
        self._existed = backup_of is None and target.exists()
        self._temp: Path | None = None
        self._fd = -1
        try:
            if backup_of is None:
                _check_writable(target)
            _remove_stale_temps(target)
            self._create_temp(data)
        except OSError as err:
            self.discard()
            raise FileWriteError(shown, _reason(err), existed=self._existed) from None
        except BaseException:
            self.discard()
            raise

    def _create_temp(self, data: bytes) -> None:
        like = self._backup_of or self.target
        for _ in range(100):
            temp = like.with_name(_temp_prefix(self.target) + secrets.token_hex(4))
            try:
                # 0o666 less the umask, as any new file: mkstemp's 0o600 would stick.
                flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC
                self._fd = os.open(temp, flags, 0o666)
            except FileExistsError:
                continue
            self._temp = temp
            break
        else:  # pragma: no cover (100 random names taken)
            raise FileExistsError(errno.EEXIST, "no free temporary name", str(like.parent))
        fcntl.flock(self._fd, fcntl.LOCK_EX)  # held until committed or discarded
        view = memoryview(data)
        while view:
            written = os.write(self._fd, view)
            view = view[written:]
        if self._backup_of is not None:
            _copy_metadata(self._backup_of, self._fd, times=True)
        elif self._existed:
            _copy_metadata(self.target, self._fd, times=False)
        os.fsync(self._fd)

    def commit(self) -> Path:
        """Put the new content in place; returns the file written."""
        temp = self._temp
        assert temp is not None, "commit after discard"
        try:
            if self._backup_of is None:
                os.replace(temp, self.target)
            else:
                self.target = _place_backup(temp, self.target)
            self._temp = None
            _sync_directory(self.target.parent)
        except OSError as err:
            self.discard()
            raise FileWriteError(self.shown, _reason(err), existed=self._existed) from None
        finally:
            self._close()
        return self.target

    def discard(self) -> None:
        """Drop the staged content (the target is untouched). Safe to call twice."""
        if self._temp is not None:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(self._temp)
            self._temp = None
        self._close()

    def _close(self) -> None:
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1


def _check_writable(target: Path) -> None:
    """Refuse what a plain ``open(path, "w")`` would refuse: renaming over a directory or a
    read-only file would succeed, but is not what the user asked for."""
    if target.is_dir():
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR))
    if target.exists() and not os.access(target, os.W_OK):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))


def _copy_metadata(source: Path, fd: int, *, times: bool) -> None:
    """Give the temporary file ``source``'s permissions (and owner, and times for a copy)."""
    st = os.stat(source)
    os.fchmod(fd, stat.S_IMODE(st.st_mode))
    mine = os.fstat(fd)
    if (mine.st_uid, mine.st_gid) != (st.st_uid, st.st_gid):
        # Only root may give a file away; anyone else keeps the file as their own.
        with contextlib.suppress(PermissionError):
            os.fchown(fd, st.st_uid, st.st_gid)
    if times:
        os.utime(fd, ns=(st.st_atime_ns, st.st_mtime_ns))


def _backup_names(first: Path) -> Iterator[Path]:
    yield first
    n = 1
    while True:
        yield first.with_name(f"{first.name}.{n}")
        n += 1


def _place_backup(temp: Path, first: Path) -> Path:
    """Move ``temp`` to the first free name of ``FILE.orig``, ``FILE.orig.1`` …, atomically:
    a hard link fails rather than replace a file that appeared in the meantime."""
    for name in _backup_names(first):
        try:
            os.link(temp, name)
        except FileExistsError:
            continue
        except OSError as err:
            if err.errno not in (errno.EPERM, errno.EOPNOTSUPP, errno.ENOTSUP):
                raise
            # No hard links here (FAT, some FUSE file systems): look, then rename.
            if os.path.lexists(name):
                continue
            os.rename(temp, name)
            return name
        os.unlink(temp)
        return name
    raise AssertionError  # pragma: no cover (the name sequence is endless)


def _sync_directory(directory: Path) -> None:
    """Make the rename itself durable (best effort: not every file system allows it)."""
    with contextlib.suppress(OSError):
        fd = os.open(directory, os.O_RDONLY | os.O_DIRECTORY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _remove_stale_temps(target: Path) -> None:
    """Remove temporary files of ``target`` whose writer died (nobody holds their lock)."""
    prefix = _temp_prefix(target)
    try:
        entries = [e for e in os.scandir(target.parent) if e.name.startswith(prefix)]
    except OSError:
        return
    for entry in entries:
        path = Path(entry.path)
        try:
            fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
        except OSError:
            continue
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                continue
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                continue  # a writer is at work on it
            # Unlink only what we locked: the name may have been renamed into place.
            if os.path.samestat(os.stat(path, follow_symlinks=False), os.fstat(fd)):
                os.unlink(path)
                logger.debug("removed %s, left by an interrupted write", path)
        except OSError:
            continue
        finally:
            os.close(fd)


def _resolve(path: str | os.PathLike[str]) -> Path:
    """The file a write to ``path`` changes: symlinks followed (a dangling one too)."""
    return Path(os.path.realpath(path))


def _encode(data: bytes | str, encoding: str) -> bytes:
    return data.encode(encoding) if isinstance(data, str) else data


def stage_write(
    path: str | os.PathLike[str],
    data: bytes | str,
    *,
    encoding: str = "utf-8",
    make_dirs: bool = False,
) -> StagedWrite:
    """Write ``data`` beside ``path``, to be put in place with :meth:`StagedWrite.commit`.

    Raises:
        FileWriteError: the data could not be written in full (nothing was changed).
    """
    target = _resolve(path)
    if make_dirs:
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise FileWriteError(path, _reason(err), existed=False) from None
    return StagedWrite(os.fspath(path), target, _encode(data, encoding))


def write_file(
    path: str | os.PathLike[str],
    data: bytes | str,
    *,
    encoding: str = "utf-8",
    make_dirs: bool = False,
) -> Path:
    """Replace ``path`` with ``data`` (text is encoded with ``encoding``), whole or not at all.

    ``make_dirs`` creates missing parent directories. Returns the file written (a symlink's
    target).

    Raises:
        FileWriteError: nothing was changed (names the file and the reason).
    """
    return stage_write(path, data, encoding=encoding, make_dirs=make_dirs).commit()


def stage_backup(path: str | os.PathLike[str], *, suffix: str = ".orig") -> StagedWrite:
    """A copy of ``path`` staged to become ``PATH.orig`` (or ``.orig.1`` … if taken).

    The backup sits beside the file a symlink points to, and keeps its permissions and times.

    Raises:
        FileWriteError: the file could not be read or the copy written (nothing was changed).
    """
    real = _resolve(path)
    try:
        data = real.read_bytes()
    except OSError as err:
        msg = f"cannot back up {os.fspath(path)}: {_reason(err)}"
        raise BelvedereError(msg) from None
    shown = os.fspath(path) + suffix
    return StagedWrite(shown, real.with_name(real.name + suffix), data, backup_of=real)


def backup_file(path: str | os.PathLike[str], *, suffix: str = ".orig") -> Path:
    """Copy ``path`` to ``PATH.orig`` — or ``PATH.orig.1``, ``.orig.2`` …: an existing backup
    is never replaced. Returns the backup's path.

    Raises:
        FileWriteError: the copy could not be written (nothing was changed).
    """
    return stage_backup(path, suffix=suffix).commit()
