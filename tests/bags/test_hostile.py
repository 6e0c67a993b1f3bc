"""Bags from the internet: decompression bombs, declared lengths and offsets that lie,
records shorter than their fixed fields, nothing playable. Each is one error or warning
naming the file and the place (``x.bag: offset N: …``), exit 1 where nothing could be
read, never a traceback, a hang or unbounded memory, and the user's file untouched."""

from __future__ import annotations

import hashlib
import logging
import os
import re
import tracemalloc
from pathlib import Path

import pytest

from belvedere.bags import BagError, Decoder, open_bag, reindex
from belvedere.cli import main
from tests.bags._hostile import (
    MCAP_FIRST_RECORD,
    ROS1_FIRST_CHUNK,
    U32,
    Chunk,
    channel,
    connection,
    fields,
    hello_chunk,
    mcap_file,
    mchunk,
    message,
    mmessage,
    mrecord,
    record,
    ros1_bag,
    schema,
    zeros_bz2,
    zeros_zstd,
)
from tests.bags._make import write_sample

BOMB = 32 << 20
"""What the bombs here inflate to, if let: far more than the bound the tests assert."""
BOUND = 4 << 20
"""What reading one of them may allocate at most (its declared size is 100 bytes)."""

SECOND = 1_000_000_000


@pytest.fixture
def warnings(caplog: pytest.LogCaptureFixture) -> pytest.LogCaptureFixture:
    caplog.set_level(logging.WARNING, logger="belvedere")
    return caplog


def _texts(caplog: pytest.LogCaptureFixture) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]


def _read_all(path: Path) -> tuple[list[int], int]:
    """(the stamps of every message read, the peak of what reading allocated)."""
    tracemalloc.start()
    try:
        bag = open_bag(path)
        try:
            stamps = [m.stamp_ns for m in bag.messages()]
        finally:
            bag.close()
        return stamps, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def _ros1_offsets(data: bytes, op: int) -> list[int]:
    """Where the records of kind ``op`` start in a ROS 1 bag built by tests.bags._hostile
    (their header's first field is ``op``)."""
    return [m.start() - 4 for m in re.finditer(b"\x04\x00\x00\x00op=" + bytes([op]), data)]


# --- decompression bombs ---------------------------------------------------------------------


def test_a_bz2_bomb_in_a_ros1_bag_stops_at_its_declared_size(
    tmp_path: Path, warnings: pytest.LogCaptureFixture, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "bomb.bag"
    bomb = hello_chunk(compression="bz2", data=zeros_bz2(BOMB), size=100)
    path.write_bytes(ros1_bag([bomb], [connection(0, "/x")]))
    stamps, peak = _read_all(path)
    assert stamps == []
    assert peak < BOUND
    assert _texts(warnings) == [
        f"{path}: offset {ROS1_FIRST_CHUNK}: chunk: inflates past its declared 100 bytes; "
        "skipping its messages"
    ]
    # reindex keeps nothing: one error, the original untouched, no backup made
    before = path.read_bytes()
    assert main(["bag", "reindex", str(path)]) == 1
    err = capsys.readouterr().err
    assert err == (
        f"error: {path}: offset {ROS1_FIRST_CHUNK}: chunk: inflates past its declared 100 "
        "bytes: no whole chunk before it to keep\n"
    )
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bomb.bag"]


def test_a_zstd_bomb_in_an_mcap_file_stops_at_its_declared_size(
    tmp_path: Path, warnings: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "bomb.mcap"
    records = mmessage(0, SECOND)
    chunk = mchunk(records, compression=b"zstd", data=zeros_zstd(BOMB), size=100)
    path.write_bytes(mcap_file([schema(), channel(), chunk], counts={0: 1}))
    chunk_at = MCAP_FIRST_RECORD + len(schema()) + len(channel())
    stamps, peak = _read_all(path)
    assert stamps == []
    assert peak < BOUND
    assert _texts(warnings) == [
        f"{path}: offset {chunk_at}: chunk: inflates past its declared 100 bytes; "
        "skipping its messages"
    ]


@pytest.mark.parametrize(
    ("compression", "data", "reason"),
    [
        ("bz2", b"BZh9garbage" * 10, "damaged bz2 data (Invalid data stream)"),
        ("lz4", b"\x04\x22\x4d\x18garbage" * 10, "damaged lz4 data (LZ4F_"),
        ("zip", b"x" * 10, "unknown compression 'zip' (known: 'none', 'bz2', 'lz4')"),
        ("none", b"x" * 10, "holds 10 bytes, not the 100 it declares"),
    ],
)
def test_a_damaged_chunk_is_one_warning_and_the_rest_plays(
    tmp_path: Path, warnings: pytest.LogCaptureFixture, compression: str, data: bytes, reason: str
) -> None:
    path = tmp_path / "bad.bag"
    good = hello_chunk(times=[SECOND])
    bad = hello_chunk(times=[2 * SECOND], compression=compression, data=data, size=100)
    path.write_bytes(ros1_bag([good, bad], [connection(0, "/x")]))
    bad_at = _ros1_offsets(path.read_bytes(), 0x05)[1]
    stamps, _ = _read_all(path)
    assert stamps == [SECOND]
    (text,) = _texts(warnings)
    assert text.startswith(f"{path}: offset {bad_at}: chunk: {reason}")
    assert text.endswith("; skipping its messages")


def test_many_damaged_chunks_are_one_warning_and_a_count(
    tmp_path: Path, warnings: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "bad.bag"
    chunks = [hello_chunk(times=[i * SECOND], data=b"", size=100) for i in range(1, 5)]
    path.write_bytes(ros1_bag(chunks, [connection(0, "/x")]))
    stamps, _ = _read_all(path)
    assert stamps == []
    first, total = _texts(warnings)
    assert first.startswith(f"{path}: offset {ROS1_FIRST_CHUNK}: chunk: holds 0 bytes")
    assert total.startswith(f"{path}: 4 damaged chunks skipped in all (the first is named above")


# --- declared lengths and offsets ------------------------------------------------------------


def test_a_chunk_data_length_past_the_end_is_located(
    tmp_path: Path, warnings: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "long.bag"
    path.write_bytes(ros1_bag([hello_chunk(data_length=0xFFFFFFF0)], [connection(0, "/x")]))
    assert _read_all(path)[0] == []
    (text,) = _texts(warnings)
    head = fields({"op": b"\x05", "compression": b"none", "size": U32.pack(0)})
    data_at = ROS1_FIRST_CHUNK + len(head) + 4  # after its header and data length
    assert text.startswith(
        f"{path}: offset {data_at}: a record's data of 4,294,967,280 bytes runs past where "
        "its section ends"
    )


def test_an_index_offset_past_the_end_is_one_error(tmp_path: Path) -> None:
    path = tmp_path / "index.bag"
    path.write_bytes(ros1_bag([hello_chunk()], [connection(0, "/x")], index_pos=1 << 40))
    with pytest.raises(
        BagError,
        match=r"index\.bag: offset 13: bag header: the index is said to "
        r"start at offset 1,099,511,627,776, outside the file's data",
    ) as caught:
        open_bag(path)
    assert caught.value.hint == f"belvedere bag reindex {path} rebuilds the index from the chunks"


def test_a_chunk_info_pointing_at_byte_0_is_skipped_and_play_ends(
    tmp_path: Path,
    warnings: pytest.LogCaptureFixture,
    endpoint: str,
    capsys: pytest.CaptureFixture[str],
) -> None:
    path = tmp_path / "zero.bag"
    data = ros1_bag([hello_chunk(pos=0)], [connection(0, "/x")])
    path.write_bytes(data)
    (info_at,) = _ros1_offsets(data, 0x06)
    assert _read_all(path)[0] == []
    (text,) = _texts(warnings)
    assert text.startswith(
        f"{path}: offset {info_at}: chunk info: its chunk is said to start at offset 0, "
        "outside the chunks"
    )
    assert main(["bag", "play", "--immediate", "-q", str(path)]) == 1
    err = capsys.readouterr().err
    assert "error: nothing played: every message read was skipped" in err


def test_reindex_of_a_message_without_its_time_is_located(tmp_path: Path) -> None:
    path = tmp_path / "short.bag"
    records = connection(0, "/x") + record_without_time()
    bag = ros1_bag([Chunk(records, [(0, SECOND)])], [connection(0, "/x")], index_pos=0)
    path.write_bytes(bag)
    time_at = len(connection(0, "/x"))
    with pytest.raises(
        BagError,
        match=rf"short\.bag: offset {ROS1_FIRST_CHUNK}: chunk, at byte {time_at} of its data: "
        r"record header: no field 'time': no whole chunk before it to keep",
    ):
        reindex(path)
    assert path.read_bytes() == bag


def record_without_time() -> bytes:
    return record({"op": b"\x02", "conn": U32.pack(0)}, b"\0\0\0\0")


def test_reindex_keeps_what_comes_before_damage(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "half.bag"
    good = hello_chunk(times=[SECOND])
    bad = hello_chunk(times=[2 * SECOND], compression="bz2", data=zeros_bz2(1 << 20), size=100)
    data = ros1_bag([good, bad], [connection(0, "/x")], index_pos=0)
    path.write_bytes(data)
    bad_at = _ros1_offsets(data, 0x05)[1]
    assert main(["bag", "reindex", str(path)]) == 0
    assert (tmp_path / "half.orig.bag").read_bytes() == data  # the original, kept
    assert capsys.readouterr().err.splitlines() == [
        f"warning: {path}: offset {bad_at}: chunk: inflates past its declared 100 bytes; the "
        "repair keeps what comes before it",
        f"{path}: 1 messages indexed; dropped {len(data) - bad_at} bytes from the damage on",
    ]
    assert _read_all(path)[0] == [SECOND]


def test_an_mcap_header_of_8_gib_is_one_error_everywhere(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "head.mcap"
    write_sample(path)
    data = bytearray(path.read_bytes())
    data[9:17] = (1 << 33).to_bytes(8, "little")
    path.write_bytes(data)
    wanted = (
        f"error: {path}: offset 17: the header record of 8,589,934,592 bytes runs past the end "
        f"of the file (at offset {len(data):,})\n"
    )
    for verb in ("info", "reindex"):
        assert main(["bag", verb, str(path)]) == 1
        assert capsys.readouterr().err == wanted
    assert path.read_bytes() == data


@pytest.mark.parametrize("where", [1 << 63, 1 << 20])
def test_an_mcap_summary_offset_past_the_end_is_one_error(tmp_path: Path, where: int) -> None:
    path = tmp_path / "summary.mcap"
    write_sample(path)
    data = bytearray(path.read_bytes())
    footer = len(data) - 37
    data[footer + 9 : footer + 17] = where.to_bytes(8, "little")
    path.write_bytes(data)
    with pytest.raises(
        BagError,
        match=rf"summary\.mcap: offset {footer}: footer: the summary is said to start "
        rf"at offset {where:,}, outside the file's records",
    ) as caught:
        open_bag(path)
    assert caught.value.hint == (
        f"belvedere bag reindex {path} writes the summary again from the data"
    )
    # reindex writes the summary again: the file reads whole
    assert reindex(path).messages == 221
    assert len(_read_all(path)[0]) == 221


def test_an_mcap_chunk_index_past_the_end_is_located_at_the_index(
    tmp_path: Path, warnings: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "index.mcap"
    chunk = mchunk(mmessage(0, SECOND))
    data = mcap_file([schema(), channel(), chunk], counts={0: 1}, chunk_pos={0: 1 << 62})
    path.write_bytes(data)
    index_at = _record_offset(data, 0x08)
    assert _read_all(path)[0] == []
    (text,) = _texts(warnings)
    assert text.startswith(
        f"{path}: offset {index_at}: chunk index: its chunk is said to start at offset "
        "4,611,686,018,427,387,904, outside the data section"
    )


def _record_offset(data: bytes, op: int) -> int:
    """The offset of the first record of kind ``op`` in an MCAP file's summary."""
    summary = int.from_bytes(data[len(data) - 37 + 9 : len(data) - 37 + 17], "little")
    pos = summary
    while data[pos] != op:
        pos += 9 + int.from_bytes(data[pos + 1 : pos + 9], "little")
    return pos


def test_an_mcap_message_shorter_than_its_fixed_fields(
    tmp_path: Path, warnings: pytest.LogCaptureFixture
) -> None:
    short = mrecord(0x05, b"\x01\x00\x00")
    loose = tmp_path / "loose.mcap"
    loose.write_bytes(mcap_file([schema(), channel(), short], summary=False))
    at = MCAP_FIRST_RECORD + len(schema()) + len(channel())
    with pytest.raises(
        BagError,
        match=rf"loose\.mcap: offset {at}: a message record of 3 bytes, shorter than its 22 "
        r"bytes of fixed fields",
    ):
        open_bag(loose)
    # inside a chunk: the messages before it are read, the rest skipped
    chunked = tmp_path / "chunked.mcap"
    records = mmessage(0, SECOND) + short + mmessage(0, SECOND)
    chunked.write_bytes(mcap_file([schema(), channel(), mchunk(records)], counts={0: 2}))
    assert _read_all(chunked)[0] == [SECOND]
    (text,) = _texts(warnings)
    assert text == (
        f"{chunked}: offset {at}: chunk, at byte {len(mmessage(0, SECOND))} of its data: a "
        "message record of 3 bytes, shorter than its 22 bytes of fixed fields; skipping the rest"
    )


def test_an_mcap_chunk_that_does_not_match_its_crc(
    tmp_path: Path, warnings: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "crc.mcap"
    path.write_bytes(mcap_file([schema(), channel(), mchunk(mmessage(0, SECOND), crc=1)]))
    assert _read_all(path)[0] == []
    at = MCAP_FIRST_RECORD + len(schema()) + len(channel())
    assert _texts(warnings) == [
        f"{path}: offset {at}: chunk: its data does not match its CRC; skipping its messages"
    ]


def test_reindex_of_a_whole_mcap_file_drops_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "whole.mcap"
    write_sample(path)
    assert main(["bag", "reindex", str(path)]) == 0
    err = capsys.readouterr().err
    assert "221 messages indexed\n" in err
    assert "dropped" not in err


# --- nothing playable ------------------------------------------------------------------------


def test_play_of_an_absent_topic_is_one_error(
    tmp_path: Path, endpoint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "sample.bag"
    write_sample(path)
    assert main(["bag", "play", "-q", str(path), "--topics", "/nope"]) == 1
    assert capsys.readouterr().err == (
        f"error: nothing to play: {path} has no topic /nope\n"
        "  hint: its topics: /map_name, /odom, /scan\n"
    )


def test_play_from_past_the_end_is_one_error(
    tmp_path: Path, endpoint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "sample.mcap"
    write_sample(path)
    assert main(["bag", "play", "-q", str(path), "-s", "1000"]) == 1
    assert capsys.readouterr().err == (
        f"error: nothing to play: -s 1000 starts after the last message, 2.0 s into {path}\n"
    )


def test_play_of_unreadable_types_is_one_error_and_one_line_each(
    tmp_path: Path,
    endpoint: str,
    warnings: pytest.LogCaptureFixture,
    capsys: pytest.CaptureFixture[str],
) -> None:
    path = tmp_path / "types.bag"
    unknown = connection(0, "/u", b"foo_msgs/Bar", b"0" * 32, b"")
    garbled = connection(1, "/v", b"foo_msgs/Baz", b"0" * 32, b"int32 x\n@@@ what ( [\n" * 20)
    records = unknown + garbled + message(0, SECOND) + message(1, SECOND)
    path.write_bytes(ros1_bag([Chunk(records, [(0, SECOND), (1, SECOND)])], [unknown, garbled]))
    assert main(["bag", "play", "-q", str(path)]) == 1
    assert capsys.readouterr().err.splitlines() == [
        f"warning: {path}: skipping /u: its type foo_msgs/msg/Bar is unknown here",
        f"warning: {path}: skipping /v (connection 1): cannot read its type foo_msgs/msg/Baz: "
        "its definition does not parse (line 2: malformed declaration '@@@ what ( [': "
        "expected TYPE NAME (or TYPE NAME=VALUE))",
        "error: nothing to play: belvedere cannot read the type of any topic chosen in "
        f"{path} (the warnings above say why)",
    ]


def test_messages_of_an_encoding_belvedere_does_not_read_are_skipped(
    tmp_path: Path, warnings: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "json.mcap"
    path.write_bytes(
        mcap_file([schema(), channel(encoding=b"json"), mchunk(mmessage(0, SECOND))], counts={0: 1})
    )
    bag = open_bag(path)
    try:
        (conn,) = bag.connections
        assert not Decoder().usable(conn)
    finally:
        bag.close()
    assert _texts(warnings) == [
        "skipping /x: its messages are encoded as 'json', which belvedere does not read"
    ]


# --- files that are not files ----------------------------------------------------------------


def test_a_fifo_given_as_a_bag_is_refused_without_blocking(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    fifo = tmp_path / "pipe.bag"
    os.mkfifo(fifo)
    for args in (
        ["bag", "info", str(fifo)],
        ["bag", "reindex", str(fifo)],
        ["slam", str(fifo), "--trajectory", str(tmp_path / "t.tum")],
    ):
        assert main(args) == 1
        err = capsys.readouterr().err
        assert (
            f"error: cannot read bag {fifo}: it is a FIFO (named pipe), not a regular file" in err
        )


def test_play_of_a_time_without_messages_ends(
    tmp_path: Path, endpoint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "sample.bag"
    write_sample(path)  # scans every 100 ms from 100 ms; the bag starts at 5 ms
    args = ["bag", "play", "-q", "--immediate", str(path), "--topics", "/scan"]
    assert main([*args, "-s", "0.001", "-u", "0.01"]) == 1
    assert capsys.readouterr().err == (
        "error: nothing played: no message falls in the time chosen\n"
    )


def test_a_type_that_holds_itself_is_skipped(
    tmp_path: Path, endpoint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "loop.bag"
    loop = connection(0, "/r", b"loop_msgs/Node", b"0" * 32, b"loop_msgs/Node next\n")
    path.write_bytes(ros1_bag([Chunk(loop + message(0, SECOND), [(0, SECOND)])], [loop]))
    assert main(["bag", "play", "-q", str(path)]) == 1
    assert capsys.readouterr().err.splitlines() == [
        f"warning: {path}: skipping /r (connection 0): cannot read its type loop_msgs/msg/Node: "
        "its definition does not parse (line 1: type 'loop_msgs/Node' contains itself)",
        "error: nothing to play: belvedere cannot read the type of any topic chosen in "
        f"{path} (the warnings above say why)",
    ]


def test_definitions_past_what_one_run_parses_are_skipped(
    warnings: pytest.LogCaptureFixture,
) -> None:
    from belvedere.bags import Connection

    decoder = Decoder()
    text = "".join(f"int32 x{i}\n" for i in range(60_000))  # 0.75 MiB: ~5 s to parse
    first_md5 = hashlib.md5(b"int32 x").hexdigest()  # genmsg's: the declarations' text
    first = Connection(0, "/a", "big_msgs/msg/A", "ros1", first_md5, "int32 x\n")
    huge = Connection(1, "/b", "big_msgs/msg/B", "ros1", "0" * 32, text * 2)
    assert decoder.usable(first)
    assert not decoder.usable(huge)
    assert _texts(warnings) == [
        "skipping /b: its type's definition (1.5 MiB) would take the definitions read past "
        "the 1 MiB belvedere parses per run"
    ]


def test_zeros_as_large_as_a_chunk_declares_stop_at_its_first_record(
    tmp_path: Path, warnings: pytest.LogCaptureFixture
) -> None:
    """A bomb that inflates to exactly its (large) declared size is read no further than
    its first record: zeros are no record in either format."""
    mcap = tmp_path / "zeros.mcap"
    chunk = mchunk(b"\0" * BOMB, compression=b"zstd", data=zeros_zstd(BOMB), crc=0)
    mcap.write_bytes(mcap_file([schema(), channel(), chunk], counts={0: 1}))
    bag = tmp_path / "zeros.bag"
    zeros = Chunk(b"\0" * BOMB, [(0, SECOND)], "bz2", zeros_bz2(BOMB))
    bag.write_bytes(ros1_bag([zeros], [connection(0, "/x")]))
    assert _read_all(mcap)[0] == []
    assert _read_all(bag)[0] == []
    chunk_at = MCAP_FIRST_RECORD + len(schema()) + len(channel())
    assert _texts(warnings) == [
        f"{mcap}: offset {chunk_at}: chunk, at byte 0 of its data: a record of kind 0x00, "
        "which the spec reserves as invalid; skipping the rest",
        f"{bag}: offset {ROS1_FIRST_CHUNK}: chunk, at byte 0 of its data: a record without "
        "its 'op' field; skipping the rest",
    ]
