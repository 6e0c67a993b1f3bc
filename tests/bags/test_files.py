"""Bag files: writing and reading both formats, rosbag info's summary, repairing a
recording that was cut short, and the errors bad files give."""

from __future__ import annotations

import shutil
from datetime import datetime
from pathlib import Path

import numpy as np
import pytest

from belvedere.bags import (
    BagError,
    Decoder,
    RecordOptions,
    bag_name,
    info_text,
    open_bag,
    parse_play_args,
    parse_record_args,
)
from belvedere.cli import main
from tests.bags._make import MS, odometry, scan, write_sample

FORMATS = [("bag", "none"), ("bag", "lz4"), ("bag", "bz2"), ("mcap", "none"), ("mcap", "lz4")]


@pytest.mark.parametrize(("ext", "compression"), FORMATS)
def test_what_is_written_reads_back(tmp_path: Path, ext: str, compression: str) -> None:
    path = tmp_path / f"sample.{ext}"
    write_sample(path, compression=compression, flush_every=50)
    bag = open_bag(path)
    try:
        conns = {c.topic: c for c in bag.connections}
        assert sorted(conns) == ["/map_name", "/odom", "/scan"]
        assert conns["/map_name"].latching
        assert not conns["/odom"].latching
        assert conns["/odom"].callerid == "/gazebo"
        assert conns["/odom"].msgtype == "nav_msgs/msg/Odometry"
        assert {t: bag.counts[c.id] for t, c in conns.items()} == {
            "/map_name": 1,
            "/odom": 200,
            "/scan": 20,
        }
        assert (bag.start_ns, bag.end_ns) == (5 * MS, 2000 * MS)
        messages = list(bag.messages())
        stamps = [m.stamp_ns for m in messages]
        assert stamps == sorted(stamps)
        odom = [Decoder().decode(m) for m in messages if m.connection.topic == "/odom"]
        assert [o.header.seq for o in odom] == list(range(200))
        assert odom[150].pose.pose.position.x == odometry(150).pose.pose.position.x
        assert odom[150].header.stamp == odometry(150).header.stamp
        scans = [Decoder().decode(m) for m in messages if m.connection.topic == "/scan"]
        np.testing.assert_array_equal(scans[7].ranges, scan(7).ranges)
        # a time window and one topic
        window = list(bag.messages([conns["/odom"]], 500 * MS, 600 * MS))
        assert [m.stamp_ns for m in window] == [n * 10 * MS for n in range(50, 60)]
        assert {c.compression for c in bag.chunks()} == {compression}
    finally:
        bag.close()


def test_info_has_rosbags_layout(tmp_path: Path, utc: None) -> None:
    path = tmp_path / "sample.bag"
    write_sample(path, flush_every=100)
    bag = open_bag(path)
    text = info_text(bag, shown_path="sample.bag")
    bag.close()
    size = path.stat().st_size / 1024
    assert text == (
        "path:        sample.bag\n"
        "version:     2.0\n"
        "duration:    2.0s\n"
        "start:       Jan 01 1970 00:00:00.01 (0.01)\n"
        "end:         Jan 01 1970 00:00:02.00 (2.00)\n"
        f"size:        {size:.1f} KB\n"
        "messages:    221\n"
        "compression: none [2/2 chunks]\n"
        "types:       nav_msgs/Odometry     [cd5e73d190d741a2f92e81eda573aca7]\n"
        "             sensor_msgs/LaserScan [90c7ef2dc6895d81024acba2ac42f369]\n"
        "             std_msgs/String       [992ce8a1687cec8c8bd883ec73ca41d1]\n"
        "topics:      /map_name     1 msg     : std_msgs/String      \n"
        "             /odom       200 msgs    : nav_msgs/Odometry    \n"
        "             /scan        20 msgs    : sensor_msgs/LaserScan"
    )


def test_info_of_compressed_mcap_and_frequencies(
    tmp_path: Path, utc: None, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "sample.mcap"
    write_sample(path, compression="lz4")
    assert main(["bag", "info", "--freq", str(path), str(path)]) == 0
    out = capsys.readouterr().out
    first, second = out.split("\n---\n")
    assert first.strip() == second.strip()
    lines = first.splitlines()
    assert lines[1] == "version:      MCAP (ros2 profile)"
    assert lines[7].startswith("compression:  lz4 [1/1 chunks; ")
    assert lines[8].startswith("uncompressed: ")
    assert lines[9].startswith("compressed:   ")
    assert "/odom       200 msgs @ 100.0 Hz : nav_msgs/Odometry" in first
    assert "/scan        20 msgs @  10.0 Hz : sensor_msgs/LaserScan" in first


def _killed_copy(path: Path, target: Path, tail: bytes) -> None:
    """What a recording killed outright leaves: the whole chunks written so far, perhaps a
    torn one after them, no index."""
    shutil.copyfile(path, target)
    with target.open("ab") as f:
        f.write(tail)


@pytest.mark.parametrize("ext", ["bag", "mcap"])
def test_reindex_repairs_a_cut_recording(
    tmp_path: Path, ext: str, capsys: pytest.CaptureFixture[str]
) -> None:
    from belvedere.bags import create_writer
    from belvedere.bags._model import encode

    active = tmp_path / f"rec.{ext}.active"
    writer = create_writer(active)
    odom = writer.add_connection("/odom", "nav_msgs/msg/Odometry", callerid="/g", latching=False)
    for i in range(120):
        writer.write(odom, (i + 1) * 10 * MS, encode(odometry(i), writer.encoding))
        if i == 99:
            writer.flush()  # what the recorder does every second
    killed = tmp_path / f"killed.{ext}"
    _killed_copy(active, killed, b"\x05\x11\x22" * 40)
    writer.close()

    with pytest.raises(BagError) as caught:
        open_bag(killed)
    assert caught.value.hint == f"belvedere bag reindex {killed}"

    assert main(["bag", "reindex", str(killed)]) == 0
    backup = tmp_path / f"killed.orig.{ext}"
    assert backup.read_bytes()[: killed.stat().st_size // 2] != b""  # the original, kept
    bag = open_bag(killed)
    stamps = [m.stamp_ns for m in bag.messages()]
    bag.close()
    assert stamps == [(i + 1) * 10 * MS for i in range(100)]
    assert (
        "100 messages indexed; dropped 120 bytes of an unfinished chunk" in capsys.readouterr().err
    )

    # a second repair would overwrite the backup: refused unless forced
    assert main(["bag", "reindex", str(killed)]) == 1
    assert "the backup" in capsys.readouterr().err
    assert main(["bag", "reindex", "-f", str(killed)]) == 0

    # into another directory, the original untouched
    out = tmp_path / "out"
    out.mkdir()
    before = backup.read_bytes()
    assert main(["bag", "reindex", "--output-dir", str(out), str(backup)]) == 0
    assert backup.read_bytes() == before
    bag = open_bag(out / backup.name)
    assert sum(bag.counts.values()) == 100
    bag.close()


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"", "is empty"),
        (b"hello world\n", "is neither a ROS 1 bag nor an MCAP file"),
        (
            b"#ROSBAG V1.2\n" + b"\0" * 64,
            "is a ROS 1 bag of format 1.2; belvedere reads 2.0",
        ),
        (
            b"#ROSBAG V2.0\n\x04",
            ": offset 13: a record's header length of 4 bytes runs past the end of the file",
        ),
        (b"\x89MCAP0\r\n\x01", "is not a whole MCAP file"),
    ],
)
def test_bad_files_give_one_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], content: bytes, message: str
) -> None:
    path = tmp_path / "x.bag"
    path.write_bytes(content)
    assert main(["bag", "info", str(path)]) == 1
    err = capsys.readouterr().err
    assert err.startswith((f"error: {path} {message}", f"error: {path}{message}"))
    assert "Traceback" not in err


def test_missing_file_and_directory(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bag", "info", str(tmp_path / "none.bag")]) == 1
    assert f"error: no such bag: {tmp_path / 'none.bag'}" in capsys.readouterr().err
    assert main(["bag", "play", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert f"error: cannot read bag {tmp_path}: it is a directory, not a regular file" in err


def test_bag_names_as_rosbag_makes_them() -> None:
    when = datetime(2024, 5, 17, 9, 3, 7)
    assert bag_name(RecordOptions(all=True), when, None) == Path("2024-05-17-09-03-07.bag")
    assert bag_name(RecordOptions(all=True, prefix="run"), when, None) == Path(
        "run_2024-05-17-09-03-07.bag"
    )
    assert bag_name(RecordOptions(all=True, prefix="run.bag"), when, None) == Path(
        "run_2024-05-17-09-03-07.bag"
    )
    assert bag_name(RecordOptions(all=True, name="x"), when, None) == Path("x.bag")
    assert bag_name(RecordOptions(all=True, name="x.mcap"), when, 2) == Path("x_2.mcap")
    assert bag_name(RecordOptions(all=True, prefix="a/b.mcap"), when, 0) == Path(
        "a/b_2024-05-17-09-03-07_0.mcap"
    )


def test_record_and_play_arguments() -> None:
    options = parse_record_args(["-a", "-x", "/camera/.*", "--split", "--duration", "5m", "--lz4"])
    assert options.all
    assert options.duration == 300.0
    assert options.compression == "lz4"
    assert options.wants("/odom")
    assert not options.wants("/camera/image_raw")
    options = parse_record_args(["-e", "/od.*", "scan", "-O", "x.bag", "--size", "2", "-l", "3"])
    assert options.wants("/odom")
    assert not options.wants("/scan")
    assert options.size == 2 * 1024 * 1024
    play = parse_play_args(["a.bag", "--clock", "-r", "2", "-s", "1.5", "--topics", "/odom", "tf"])
    assert play.bags == (Path("a.bag"),)
    assert play.topics == frozenset({"/odom", "/tf"})
    assert (play.clock, play.rate, play.start) == (True, 2.0, 1.5)


@pytest.mark.parametrize(
    ("words", "message"),
    [
        ([], "you must name topics to record, or use -a"),
        (["-a", "-o", "p", "-O", "n"], "cannot use both -o (a name prefix) and -O (the name)"),
        (["-a", "--bz2", "--lz4"], "cannot use both --bz2 and --lz4"),
        (["-a", "--split"], "--split needs --size or --duration"),
        (["-a", "--duration", "soon"], "expected a positive duration"),
        (["-e", "(unclosed"], "bad regular expression '(unclosed'"),
        (["-a", "--max-splits", "2"], "--max-splits is for --split"),
        (["-a", "--frobnicate"], "unexpected arguments --frobnicate"),
    ],
)
def test_record_argument_errors(words: list[str], message: str) -> None:
    with pytest.raises(BagError, match=None) as caught:
        parse_record_args(words)
    assert message in caught.value.message


def test_mcap_with_bz2_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bag", "record", "-a", "-O", str(tmp_path / "x.mcap"), "-j"]) == 1
    assert "MCAP has no bz2 compression" in capsys.readouterr().err
