"""``rosbag record`` and ``rosbag play``'s command lines, for ``belvedere bag`` and for
``<node pkg="rosbag" …>`` in launch files alike."""

from __future__ import annotations

import argparse
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from typing import NoReturn

from belvedere.bags._model import BagError
from belvedere.graph import resolve_name

__all__ = [
    "PlayOptions",
    "RecordOptions",
    "add_play_options",
    "add_record_options",
    "bag_name",
    "parse_duration",
    "parse_play_args",
    "parse_record_args",
    "play_options",
    "record_options",
]


def parse_duration(text: str) -> float:
    """rosbag's durations: seconds, or with ``s``, ``m`` or ``h`` appended."""
    value = text.strip()
    scale = {"s": 1.0, "m": 60.0, "h": 3600.0}.get(value[-1:].lower())
    number = value[:-1] if scale is not None else value
    try:
        seconds = float(number) * (scale or 1.0)
    except ValueError:
        seconds = float("nan")
    if not seconds > 0 or seconds == float("inf"):
        msg = f"expected a positive duration (seconds, or with m or h appended), got {text!r}"
        raise argparse.ArgumentTypeError(msg)
    return seconds


def _positive(kind: type[float] | type[int]) -> Callable[[str], float | int]:
    def parse(text: str) -> float | int:
        try:
            value = kind(text)
        except ValueError:
            value = -1
        if not value > 0:
            msg = f"expected a positive number, got {text!r}"
            raise argparse.ArgumentTypeError(msg)
        return value

    parse.__name__ = kind.__name__
    return parse


def _non_negative(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not value >= 0 or value == float("inf"):
        msg = f"expected a number of seconds (0 or more), got {text!r}"
        raise argparse.ArgumentTypeError(msg)
    return value


# --- record ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class RecordOptions:
    topics: tuple[str, ...] = ()
    all: bool = False
    regex: bool = False
    """The topics are regular expressions."""
    exclude: re.Pattern[str] | None = None
    prefix: str | None = None
    name: str | None = None
    split: bool = False
    max_splits: int | None = None
    size: int | None = None
    """Bytes."""
    duration: float | None = None
    """Seconds (of the graph's time)."""
    limit: int | None = None
    """Messages per topic."""
    compression: str = "none"
    chunk_size: int | None = None
    repeat_latched: bool = False
    quiet: bool = False

    def wants(self, topic: str) -> bool:
        """Is ``topic`` one to record?"""
        if self.exclude is not None and self.exclude.search(topic):
            return False
        if self.all:
            return True
        if self.regex:
            return any(re.fullmatch(p, topic) for p in self.topics)
        return topic in self.topics


def add_record_options(p: argparse.ArgumentParser, *, quiet: bool = True) -> None:
    p.add_argument("topics", nargs="*", metavar="TOPIC", help="topics to record")
    p.add_argument("-a", "--all", action="store_true", help="record all topics")
    p.add_argument(
        "-e", "--regex", action="store_true", help="match topics using regular expressions"
    )
    p.add_argument(
        "-x",
        "--exclude",
        metavar="EXCLUDE_REGEX",
        help="exclude topics matching the regular expression (subtracts from -a or regex)",
    )
    if quiet:
        p.add_argument("-q", "--quiet", action="store_true", help="suppress console output")
    p.add_argument(
        "-o",
        "--output-prefix",
        metavar="PREFIX",
        help="prepend PREFIX to the bag's name (which always ends with a date stamp); "
        "PREFIX.mcap records MCAP",
    )
    p.add_argument(
        "-O",
        "--output-name",
        metavar="NAME",
        help="record to NAME.bag (NAME.mcap: an MCAP file)",
    )
    p.add_argument(
        "--split", action="store_true", help="split the bag when --size or --duration is reached"
    )
    p.add_argument(
        "--max-splits",
        type=_positive(int),
        metavar="N",
        help="keep at most N bag files, erasing the oldest",
    )
    p.add_argument(
        "--size", type=_positive(float), metavar="MB", help="record a bag of at most MB megabytes"
    )
    p.add_argument(
        "--duration",
        type=parse_duration,
        metavar="DURATION",
        help="record a bag of at most DURATION seconds (of the graph's time; 'm' or 'h' "
        "appended: minutes, hours)",
    )
    p.add_argument(
        "-l", "--limit", type=_positive(int), metavar="NUM", help="record NUM messages per topic"
    )
    p.add_argument("-j", "--bz2", action="store_true", help="use BZ2 compression")
    p.add_argument("--lz4", action="store_true", help="use LZ4 compression")
    p.add_argument(
        "--chunksize",
        type=_positive(int),
        metavar="KB",
        help="write chunks of KB kilobytes (default: 768)",
    )
    p.add_argument(
        "--repeat-latched",
        action="store_true",
        help="repeat latched messages at the start of each new bag file",
    )
    p.add_argument(
        "-b", "--buffsize", metavar="MB", help="(accepted for rosbag's sake; nothing is dropped)"
    )
    p.add_argument("--tcpnodelay", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--udp", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--node", metavar="NODE", help=argparse.SUPPRESS)


def record_options(args: argparse.Namespace, *, quiet: bool = False) -> RecordOptions:
    """Check a parsed ``record`` command line (one clear error for what rosbag refuses)."""
    if args.node:
        msg = "--node (record what one node subscribes to) is not supported; name the topics"
        raise BagError(msg)
    if not args.all and not args.topics:
        msg = "you must name topics to record, or use -a (all topics)"
        raise BagError(msg, hint="e.g. belvedere bag record -a, or bag record /odom /scan")
    if args.output_prefix and args.output_name:
        msg = "cannot use both -o (a name prefix) and -O (the name)"
        raise BagError(msg)
    if args.bz2 and args.lz4:
        msg = "cannot use both --bz2 and --lz4: choose one compression"
        raise BagError(msg)
    if args.split and args.size is None and args.duration is None:
        msg = "--split needs --size or --duration (where to split)"
        raise BagError(msg)
    if args.max_splits is not None and not args.split:
        msg = "--max-splits is for --split"
        raise BagError(msg)
    exclude = None
    patterns = [args.exclude] if args.exclude else []
    if args.regex:
        patterns += args.topics
    for pattern in patterns:
        try:
            compiled = re.compile(pattern)
        except re.error as err:
            msg = f"bad regular expression {pattern!r}: {err}"
            raise BagError(msg) from None
        if pattern == args.exclude:
            exclude = compiled
    topics = tuple(args.topics if args.regex else (resolve_name(t) for t in args.topics))
    return RecordOptions(
        topics=topics,
        all=args.all,
        regex=args.regex,
        exclude=exclude,
        prefix=args.output_prefix,
        name=args.output_name,
        split=args.split,
        max_splits=args.max_splits,
        size=None if args.size is None else round(args.size * 1024 * 1024),
        duration=args.duration,
        limit=args.limit,
        compression="bz2" if args.bz2 else "lz4" if args.lz4 else "none",
        chunk_size=None if args.chunksize is None else args.chunksize * 1024,
        repeat_latched=args.repeat_latched,
        quiet=quiet or bool(getattr(args, "quiet", False)),
    )


def bag_name(options: RecordOptions, when: datetime, split: int | None) -> Path:
    """The file to record to, as rosbag names it: ``-O NAME`` → ``NAME.bag``; ``-o PREFIX``
    → ``PREFIX_YYYY-MM-DD-HH-MM-SS.bag``; neither → ``YYYY-MM-DD-HH-MM-SS.bag``; split
    files end ``_0``, ``_1``… A name ending ``.mcap`` records MCAP."""
    base = options.name if options.name is not None else options.prefix or ""
    ext = ".bag"
    for suffix in (".bag", ".mcap"):
        if base.endswith(suffix):
            base, ext = base[: -len(suffix)], suffix
    parts = [base] if base else []
    if options.name is None:
        parts.append(when.strftime("%Y-%m-%d-%H-%M-%S"))
    if split is not None:
        parts.append(str(split))
    if not parts:
        msg = "the bag's name is empty"
        raise BagError(msg)
    return Path("_".join(parts) + ext)


# --- play ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PlayOptions:
    bags: tuple[Path, ...]
    topics: frozenset[str] | None = None
    pause_topics: frozenset[str] = frozenset()
    prefix: str = ""
    quiet: bool = False
    immediate: bool = False
    pause: bool = False
    clock: bool = False
    hz: float = 100.0
    delay: float = 0.2
    rate: float = 1.0
    start: float = 0.0
    duration: float | None = None
    skip_empty: float | None = None
    loop: bool = False
    keep_alive: bool = False
    wait_for_subscribers: bool = False
    remappings: dict[str, str] = field(default_factory=dict)


def add_play_options(p: argparse.ArgumentParser, *, quiet: bool = True) -> None:
    p.add_argument("bags", nargs="*", metavar="BAGFILE", help="bag (or MCAP) files to play")
    p.add_argument("-p", "--prefix", default="", metavar="PREFIX", help="prefix all topics")
    if quiet:
        p.add_argument("-q", "--quiet", action="store_true", help="suppress console output")
    p.add_argument(
        "-i", "--immediate", action="store_true", help="play back all messages without waiting"
    )
    p.add_argument("--pause", action="store_true", help="start paused (space resumes)")
    p.add_argument("--queue", metavar="SIZE", help="(accepted for rosbag's sake)")
    p.add_argument(
        "--clock",
        action="store_true",
        help="publish /clock and run in the bag's (simulated) time",
    )
    p.add_argument(
        "--hz",
        type=_positive(float),
        default=100.0,
        metavar="HZ",
        help="publish /clock at HZ (default: 100)",
    )
    p.add_argument(
        "-d",
        "--delay",
        type=_non_negative,
        default=0.2,
        metavar="SEC",
        help="wait SEC seconds after advertising the topics (default: 0.2)",
    )
    p.add_argument(
        "-r",
        "--rate",
        type=_positive(float),
        default=1.0,
        metavar="FACTOR",
        help="multiply the publish rate by FACTOR",
    )
    p.add_argument(
        "-s",
        "--start",
        type=_non_negative,
        default=0.0,
        metavar="SEC",
        help="start SEC seconds into the bags",
    )
    p.add_argument(
        "-u",
        "--duration",
        type=_positive(float),
        metavar="SEC",
        help="play only SEC seconds of the bags",
    )
    p.add_argument(
        "--skip-empty",
        type=_positive(float),
        metavar="SEC",
        help="skip stretches with no messages longer than SEC seconds",
    )
    p.add_argument("-l", "--loop", action="store_true", help="loop playback")
    p.add_argument(
        "-k", "--keep-alive", action="store_true", help="keep running after the end of the bags"
    )
    p.add_argument("--topics", nargs="+", metavar="TOPIC", help="play only these topics")
    p.add_argument(
        "--pause-topics", nargs="+", metavar="TOPIC", help="pause after a message on these"
    )
    p.add_argument("--bags", dest="more_bags", nargs="+", metavar="BAG", help="more bags")
    p.add_argument(
        "--wait-for-subscribers",
        action="store_true",
        help="wait for a subscriber on each topic before publishing",
    )


def play_options(
    args: argparse.Namespace, *, extra: list[str] | None = None, quiet: bool = False
) -> PlayOptions:
    """Check a parsed ``play`` command line; ``extra``: ``from:=to`` remappings."""
    bags = list(args.bags) + list(args.more_bags or [])
    topics = list(args.topics or [])
    # --topics takes words up to the next option: bag files written after it are bags
    for word in list(topics):
        if word.endswith((".bag", ".mcap")) and Path(word).is_file():
            topics.remove(word)
            bags.append(word)
    if not bags:
        msg = "you must name at least one bag file to play"
        raise BagError(msg)
    remaps = {}
    for word in extra or []:
        key, sep, value = word.partition(":=")
        if not sep or not key or key.startswith("_"):
            msg = f"unexpected argument {word!r}"
            raise BagError(msg, hint="belvedere bag play [options] BAGFILE… [from:=to …]")
        remaps[resolve_name(key)] = resolve_name(value)
    return PlayOptions(
        bags=tuple(Path(b) for b in bags),
        topics=frozenset(resolve_name(t) for t in topics) if args.topics else None,
        pause_topics=frozenset(resolve_name(t) for t in args.pause_topics or ()),
        prefix=args.prefix,
        quiet=quiet or bool(getattr(args, "quiet", False)),
        immediate=args.immediate,
        pause=args.pause,
        clock=args.clock,
        hz=args.hz,
        delay=args.delay,
        rate=args.rate,
        start=args.start,
        duration=args.duration,
        skip_empty=args.skip_empty,
        loop=args.loop,
        keep_alive=args.keep_alive,
        wait_for_subscribers=args.wait_for_subscribers,
        remappings=remaps,
    )


# --- launch files' args="…" ------------------------------------------------------------------


class _Parser(argparse.ArgumentParser):
    """Errors are :class:`BagError` (a launch file's node fails at its line), not exits."""

    def error(self, message: str) -> NoReturn:
        msg = f"rosbag {self.prog.split()[-1]}: {message}"
        raise BagError(msg)

    def exit(self, status: int = 0, message: str | None = None) -> NoReturn:
        raise BagError(message or f"rosbag {self.prog.split()[-1]} exited")


def parse_record_args(words: list[str]) -> RecordOptions:
    parser = _Parser(prog="rosbag record", add_help=False)
    add_record_options(parser)
    args, extra = parser.parse_known_args(words)
    if extra:
        msg = f"rosbag record: unexpected arguments {' '.join(extra)}"
        raise BagError(msg)
    return record_options(args)


def parse_play_args(words: list[str]) -> PlayOptions:
    parser = _Parser(prog="rosbag play", add_help=False)
    add_play_options(parser)
    args, extra = parser.parse_known_args(words)
    return play_options(args, extra=extra)
