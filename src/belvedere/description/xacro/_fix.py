"""``--fix``: rewrite legacy xacro files to the prefixed syntax modern xacro understands.

We expand the file in the ``auto`` dialect, which records every unprefixed tag it treated
as a xacro keyword or macro call, then edit exactly those start and end tags in the files
where they are written — nothing else in the text changes. Each file is kept as
``FILE.orig`` (``FILE.orig.1`` … if that exists) and replaced atomically
(:mod:`belvedere.fileio`).
"""

from __future__ import annotations

import logging
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path
from xml.parsers import expat

from belvedere.bounded import TEXT_FILE_BYTES, read_regular
from belvedere.description.xacro._api import expand_file
from belvedere.description.xacro._dialects import Dialect, XacroWarning
from belvedere.description.xacro._errors import XacroError
from belvedere.errors import SourceLocation
from belvedere.fileio import StagedWrite, stage_backup, stage_write
from belvedere.packages import PackageIndex

__all__ = ["FixChange", "fix_file", "fix_text"]

logger = logging.getLogger("belvedere.xacro")

XACRO_NS = "http://www.ros.org/wiki/xacro"


@dataclass(frozen=True, slots=True)
class FixChange:
    """One tag rewritten."""

    location: SourceLocation
    old: str
    new: str

    def __str__(self) -> str:
        return f"{self.location}: <{self.old}> -> <{self.new}>"


def _tag_offsets(
    data: bytes, wanted: set[tuple[int, int]]
) -> dict[tuple[int, int], tuple[int, int | None]]:
    """Byte offsets of the start and end tags of elements starting at ``wanted`` (line, col)."""
    found: dict[tuple[int, int], tuple[int, int | None]] = {}
    stack: list[tuple[tuple[int, int], int]] = []
    p = expat.ParserCreate()
    p.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)

    def start(name: str, attrs: object) -> None:
        stack.append(((p.CurrentLineNumber, p.CurrentColumnNumber + 1), p.CurrentByteIndex))

    def end(name: str) -> None:
        pos, start_at = stack.pop()
        if pos in wanted:
            at = p.CurrentByteIndex
            found[pos] = (start_at, at if data[at : at + 2] == b"</" else None)

    p.StartElementHandler = start
    p.EndElementHandler = end
    p.Parse(data, True)
    return found


def fix_text(
    data: bytes, sites: dict[tuple[int, int], str], path: str
) -> tuple[bytes, list[FixChange]]:
    """Prefix the tags at ``sites`` ((line, col) → tag) with ``xacro:``; declare the namespace."""
    offsets = _tag_offsets(data, set(sites))
    edits: list[tuple[int, bytes, bytes]] = []  # (offset, old, new)
    changes: list[FixChange] = []
    for (line, col), tag in sorted(sites.items()):
        if (line, col) not in offsets:
            continue
        start, end = offsets[(line, col)]
        old = tag.encode()
        edits.append((start, b"<" + old, b"<xacro:" + old))
        if end is not None:
            edits.append((end, b"</" + old, b"</xacro:" + old))
        changes.append(FixChange(SourceLocation(path, line, col), tag, f"xacro:{tag}"))
    if not edits:
        return data, []
    out = bytearray(data)
    for offset, old, new in sorted(edits, reverse=True):
        if bytes(out[offset : offset + len(old)]) != old:
            msg = f"cannot rewrite <{old.decode()}> at byte {offset}: unexpected text"
            raise XacroError(msg, SourceLocation(path))
        out[offset : offset + len(old)] = new
    fixed = bytes(out)
    if b"xmlns:xacro" not in fixed:
        fixed = _declare_namespace(fixed)
    return fixed, changes


def _declare_namespace(data: bytes) -> bytes:
    """Add ``xmlns:xacro`` to the root element's start tag."""
    p = expat.ParserCreate()
    root_at: list[int] = []

    def start(name: str, attrs: object) -> None:
        if not root_at:
            root_at.append(p.CurrentByteIndex)
            root_at.append(len(name))

    p.StartElementHandler = start
    p.Parse(data, True)
    at = root_at[0] + 1 + root_at[1]
    return data[:at] + f' xmlns:xacro="{XACRO_NS}"'.encode() + data[at:]


def fix_file(
    path: str | Path,
    *,
    mappings: dict[str, str] | None = None,
    packages: PackageIndex | None = None,
    root_dir: str | None = None,
) -> list[FixChange]:
    """Rewrite ``path`` and the files it includes in place; returns what changed."""
    expansion = expand_file(
        path,
        mappings=mappings,
        dialect=Dialect.AUTO,
        packages=packages,
        root_dir=root_dir,
        on_warning=_other_than_legacy,  # the legacy ones are what is fixed, and reported so
    )
    by_file: dict[str, dict[tuple[int, int], str]] = defaultdict(dict)
    for loc, tag in expansion.legacy_sites:
        by_file[loc.path][(loc.line, loc.col)] = tag
    # Compute every edit before writing any file: all or nothing.
    planned: list[tuple[Path, bytes, list[FixChange]]] = []
    for name, sites in by_file.items():
        file = Path(root_dir, name) if root_dir else Path(name)
        # (LimitError if the file changed into a FIFO or grew past the cap since it was read)
        fixed, changes = fix_text(read_regular(file, limit=TEXT_FILE_BYTES, what=""), sites, name)
        if changes:
            planned.append((file, fixed, changes))
    _write_all([(file, fixed) for file, fixed, _ in planned])
    return [change for _, _, changes in planned for change in changes]


def _other_than_legacy(warning: XacroWarning) -> None:
    if warning.legacy is None:
        logger.warning("%s", warning)


def _write_all(files: list[tuple[Path, bytes]]) -> None:
    """Back up and rewrite every file, or none: every backup and new content is written in
    full beside its file before any is put in place, so a full disk stops the lot."""
    backups: list[StagedWrite] = []
    rewrites: list[StagedWrite] = []
    try:
        for file, data in files:
            backups.append(stage_backup(file))
            rewrites.append(stage_write(file, data))
        # Only renames from here on: nothing left to run out of space.
        for (file, _), backup in zip(files, backups, strict=True):
            logger.info("%s: the original is kept as %s", file, backup.commit())
        for rewrite in rewrites:
            rewrite.commit()
    finally:
        for pending in (*backups, *rewrites):
            pending.discard()  # what was not committed (a no-op for what was)
