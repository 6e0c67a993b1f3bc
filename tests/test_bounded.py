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
    check_pixels,
    describe_size,
    inflate,
    read_regular,
    read_regular_text,
    run_bounded,
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


def test_a_file_is_named_as_the_caller_shows_it(tmp_path: Path) -> None:
    with pytest.raises(LimitError, match=r"^error: cannot read 'x\.yaml': No such file"):
        read_regular(tmp_path / "x.yaml", what="", name="'x.yaml'")


def test_text_that_is_not_utf8_is_refused_at_its_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "a.txt"
    path.write_bytes("é\nab\xff".encode("latin-1"))  # é is not UTF-8 either: line 1 first
    with pytest.raises(LimitError, match=r"a\.txt:1:1: error: .*not UTF-8 text \(byte 0xe9\)"):
        read_regular_text(path)
    path.write_bytes("é\nab".encode() + b"\xff")
    with pytest.raises(LimitError, match=r"a\.txt:2:3: error: .*not UTF-8 text \(byte 0xff\)"):
        read_regular_text(path)
    path.write_bytes("é\n".encode())
    assert read_regular_text(path) == "é\n"


def test_pixels_past_the_cap_are_refused_with_the_size() -> None:
    assert check_pixels(8192, 8192) == 1 << 26
    with pytest.raises(
        LimitError,
        match=r"^error: the map is 8,193 x 8,192 pixels \(67,117,056\), more than the "
        r"67,108,864 \(8192 x 8192\) belvedere decodes$",
    ):
        check_pixels(8193, 8192, what="the map")


def test_a_program_gets_its_input_and_gives_its_output() -> None:
    data = bytes(range(256)) * 2000  # more than a pipe holds: written as it is read
    ran = run_bounded(["cat"], seconds=60, limit=len(data), stdin=data)
    assert (ran.status, ran.stdout, ran.stderr, ran.stopped) == (0, data, b"", "")


def test_a_program_that_prints_past_the_limit_is_stopped() -> None:
    ran = run_bounded(["yes"], seconds=60, limit=1 << 16)
    assert (ran.status, ran.stdout, ran.stopped) == (None, b"", "stdout")


def test_a_program_that_does_not_stop_reading_its_input_is_not_waited_on() -> None:
    ran = run_bounded(["sleep", "60"], seconds=0.2, limit=1 << 16, stdin=b"x" * (1 << 20))
    assert (ran.status, ran.stopped) == (None, "time")
