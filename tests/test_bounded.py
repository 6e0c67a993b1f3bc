"""Bounded reads: only regular files, within a size; inflating within the declared size."""

from __future__ import annotations

import bz2
import gzip
import os
from pathlib import Path

import lz4.frame
import pytest

from belvedere.bounded import (
    LimitError,
    _zstd,
    check_count,
    describe_size,
    inflate,
    read_regular,
)
from belvedere.errors import SourceLocation


def test_reads_a_regular_file(tmp_path: Path) -> None:
    path = tmp_path / "a.yaml"
    path.write_bytes(b"a: 1\n")
    assert read_regular(path) == b"a: 1\n"


def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path: Path) -> None:
    fifo = tmp_path / "map.pgm"
    os.mkfifo(fifo)
    at = SourceLocation("map.yaml", 2, 1)
    with pytest.raises(LimitError, match=r"FIFO \(named pipe\), not a regular file") as err:
        read_regular(fifo, what="map image", at=at)
    assert err.value.describe().startswith("map.yaml:2:1: error: cannot read map image ")


@pytest.mark.parametrize(
    ("path", "kind"), [("/dev/zero", "a character device"), ("/", "a directory")]
)
def test_special_files_are_refused(path: str, kind: str) -> None:
    with pytest.raises(LimitError, match=f"it is {kind}, not a regular file"):
        read_regular(path)


def test_a_file_past_the_limit_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "big.launch"
    path.write_bytes(b"x" * 2048)
    with pytest.raises(LimitError, match=r"it is 2 KiB, more than the 1 KiB belvedere reads"):
        read_regular(path, limit=1024, what="launch file")
    assert read_regular(path, limit=2048) == b"x" * 2048


def test_a_missing_file_names_the_reason(tmp_path: Path) -> None:
    with pytest.raises(LimitError, match=r"cannot read file .*nope: No such file"):
        read_regular(tmp_path / "nope")


def _compress(codec: str, data: bytes) -> bytes:
    if codec == "bz2":
        return bz2.compress(data)
    if codec == "lz4":
        return bytes(lz4.frame.compress(data))
    if codec == "zstd":
        return bytes(_zstd().compress(data))
    return gzip.compress(data)


CODECS = ("bz2", "lz4", "zstd", "gzip")


@pytest.mark.parametrize("codec", CODECS)
def test_inflate_gives_the_declared_bytes(codec: str) -> None:
    data = bytes(range(256)) * 100
    assert inflate(codec, _compress(codec, data), size=len(data), where="x") == data


@pytest.mark.parametrize("codec", CODECS)
def test_a_bomb_stops_at_its_declared_size(codec: str) -> None:
    bomb = _compress(codec, bytes(64 << 20))  # 64 MiB of zeros: a few KiB compressed
    assert len(bomb) < 1 << 20
    with pytest.raises(
        LimitError, match=r"error: a.bag: offset 4117: inflates past its declared 1,000"
    ):
        inflate(codec, bomb, size=1000, where="a.bag: offset 4117")


@pytest.mark.parametrize("codec", CODECS)
def test_short_and_damaged_data_are_refused(codec: str) -> None:
    data = _compress(codec, b"hello")
    with pytest.raises(LimitError, match=r"inflates to 5 bytes, not the 6 it declares"):
        inflate(codec, data, size=6, where="w")
    with pytest.raises(LimitError, match=f"error: w: damaged {codec} data"):
        inflate(codec, b"\x00garbage" * 8, size=6, where="w")


def test_a_declared_size_past_the_cap_is_refused_before_inflating() -> None:
    with pytest.raises(LimitError, match=r"declares 4,294,967,280 bytes uncompressed, more than"):
        inflate("bz2", b"", size=0xFFFFFFF0, where="c")
    with pytest.raises(LimitError, match="unknown compression 'rar'"):
        inflate("rar", b"", size=1, where="c")


def test_counts_and_sizes() -> None:
    assert check_count(10, 10, "beams") == 10
    with pytest.raises(
        LimitError, match=r"error: scan.bag: beams: 5,000,000 is more than the cap of 65,536"
    ):
        check_count(5_000_000, 65_536, "beams", where="scan.bag")
    assert describe_size(812) == "812 bytes"
    assert describe_size(3 << 29) == "1.5 GiB"
