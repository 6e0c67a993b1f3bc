"""``belvedere bag record|play|info|reindex`` — rosbag, on belvedere's graph.

``record`` and ``play`` take rosbag's options. A ``.bag`` file is a ROS 1 bag (ROS 1's
rosbag reads it), a ``.mcap`` file MCAP (Foxglove reads it). ``record`` stamps each message
with the graph's time when it arrives (simulated time in a simulation, as rosbag with
``use_sim_time``) and writes a chunk at least every second: a recording killed outright
loses at most its last second, and ``reindex`` repairs the file. ``play --clock`` runs in the
bag's own time and publishes ``/clock``; with ``--rtf max`` as fast as the CPU allows.
"""

from __future__ import annotations

import argparse
import contextlib
import logging
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from types import FrameType

from belvedere.bags import (
    BagError,
    BagFile,
    Player,
    PlayOptions,
    PlayProgress,
    ProgressBar,
    Recorder,
    TapRecording,
    add_play_options,
    add_record_options,
    info_text,
    open_bag,
    play_options,
    record_options,
    reindex,
    wants_progress,
)
from belvedere.cli._script import parse_rtf
from belvedere.cli._tool import action_parsers, graph_address
from belvedere.errors import BelvedereError
from belvedere.graph import Graph
from belvedere.runtime import join_ros_master, open_clock_transport, open_transport

__all__ = ["add_parser", "run"]

logger = logging.getLogger("belvedere.cli")


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "bag",
        parents=[common],
        help="record and play back topics (rosbag)",
        description="Record topics to bag files and play them back, as rosbag does. .bag "
        "files are ROS 1 bags, .mcap files MCAP.",
    )
    action = action_parsers(p, common)
    v = action("record", "record topics to a bag file")
    add_record_options(v, quiet=False)
    v = action("play", "play back bag files")
    add_play_options(v, quiet=False)
    v.add_argument(
        "--rtf",
        type=parse_rtf,
        default=False,
        metavar="N|max",
        help="with --clock: the pace of the bag's time (default: the --rate); max: as fast "
        "as possible",
    )
    v = action("info", "summarize bag files (as rosbag info)")
    v.add_argument("files", nargs="+", metavar="BAGFILE")
    v.add_argument("--freq", action="store_true", help="show each topic's message rate")
    v = action("reindex", "repair bag files whose recording was cut short")
    v.add_argument("files", nargs="+", metavar="BAGFILE")
    v.add_argument("--output-dir", metavar="DIR", help="write the repaired files to DIR")
    v.add_argument("-f", "--force", action="store_true", help="overwrite a backup file that exists")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    actions = {"record": _record, "play": _play, "info": _info, "reindex": _reindex}
    if args.extra and args.action != "play":
        msg = f"unexpected arguments: {' '.join(args.extra)}"
        raise BelvedereError(msg)
    return actions[args.action](args)


# --- info, reindex -----------------------------------------------------------------------------


def _info(args: argparse.Namespace) -> int:
    texts = []
    for name in args.files:
        bag = open_bag(name)
        try:
            texts.append(info_text(bag, freq=args.freq, shown_path=name))
        finally:
            bag.close()
    sys.stdout.write("\n---\n".join(texts) + "\n")
    return 0


def _reindex(args: argparse.Namespace) -> int:
    output_dir = Path(args.output_dir) if args.output_dir else None
    if output_dir is not None and not output_dir.is_dir():
        msg = f"--output-dir {output_dir}: no such directory"
        raise BagError(msg)
    failed = 0
    for name in args.files:
        try:
            done = reindex(Path(name), output_dir=output_dir, force=args.force)
        except BelvedereError as err:
            sys.stderr.write(err.describe() + "\n")
            failed += 1
            continue
        if done.damage is not None:
            logger.warning("%s; the repair keeps what comes before it", done.damage)
        tail = ""
        if done.dropped:
            what = "of an unfinished chunk" if done.damage is None else "from the damage on"
            tail = f"; dropped {done.dropped} bytes {what}"
        logger.info("%s: %d messages indexed%s", done.output, done.messages, tail)
    return 1 if failed else 0


# --- record --------------------------------------------------------------------------------------


@contextlib.contextmanager
def _stop_on_signals(stop: threading.Event) -> Iterator[None]:
    """SIGINT and SIGTERM end the run cleanly (roslaunch and kill send them)."""

    def handler(signum: int, frame: FrameType | None) -> None:
        stop.set()

    old = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)


def _record(args: argparse.Namespace) -> int:
    if getattr(args, "ros_master", None):
        msg = "bag record does not join a ROS 1 master yet (--ros-master)"
        raise BelvedereError(
            msg,
            hint="record there with ROS 1's own `rosbag record`, or bridge the graph with "
            "`belvedere roscore` and record with belvedere",
        )
    options = record_options(args, quiet=args.quiet > 0)
    timed = options.duration is not None and not options.split
    bar = ProgressBar(
        "recording", options.duration or 0.0, enabled=timed and wants_progress(options.quiet)
    )
    recorder = Recorder(
        options, on_progress=(lambda s: bar.update(s, f"{s:.1f} s")) if bar.enabled else None
    )
    transport = open_transport(graph_address(args), serve_params=False)
    stop = threading.Event()
    try:
        with _stop_on_signals(stop):
            recorder.start(TapRecording(transport, recorder))
            while not stop.is_set() and not recorder.finished.is_set():
                stop.wait(0.1)
    finally:
        try:
            recorder.stop()
        finally:
            bar.close()
            transport.close()
    return 0


# --- play ----------------------------------------------------------------------------------------


def _play(args: argparse.Namespace) -> int:
    options = play_options(args, extra=list(args.extra), quiet=args.quiet > 0)
    if args.rtf is not False and not options.clock:
        msg = "--rtf paces the bag's own time: it goes with --clock (else use -r RATE)"
        raise BagError(msg)
    bags: list[BagFile] = []
    try:
        for path in options.bags:
            if not options.quiet:
                logger.info("Opening %s", path)
            bags.append(open_bag(path))
        return _play_bags(args, options, bags)
    finally:
        for bag in bags:
            bag.close()


def _play_bags(args: argparse.Namespace, options: PlayOptions, bags: list[BagFile]) -> int:
    # --clock: the bag's time is the graph's one clock
    transport = open_clock_transport(graph_address(args), clock=options.clock, serve_params=False)
    graph = Graph(
        sim_time=options.clock,
        transport=transport,
        clock_hz=options.hz if options.clock else None,
    )
    join_ros_master(graph, graph_address(args))
    bar: ProgressBar | None = None
    stop = threading.Event()
    try:
        node = graph.create_node(f"play_{os.getpid()}", remappings=options.remappings)
        shown = _PlayBar()
        player = Player(node, options, bags=bags, on_progress=shown)
        bar = shown.bar = ProgressBar(
            "[RUNNING]", player.total_s, enabled=wants_progress(options.quiet)
        )
        _wait_before_playing(player, options.delay, options.wait_for_subscribers, options.quiet)
        keys = _keyboard(player) if sys.stdin.isatty() and not options.quiet else None
        player.start()
        rtf = options.rate if args.rtf is False else args.rtf
        with _stop_on_signals(stop):
            runner = threading.Thread(
                target=graph.run,
                kwargs={"rtf": rtf, "until": lambda: player.done.is_set() or stop.is_set()},
                daemon=True,
            )
            runner.start()
            while runner.is_alive() and not stop.is_set():
                runner.join(0.1)
            graph.executor.stop()
            runner.join()
        if keys is not None:
            keys.close()
        transport.flush()
    finally:
        if bar is not None:
            bar.close()
        graph.shutdown()
    if player.published == 0 and not stop.is_set():
        why = (
            "every message read was skipped (the warnings above say why)"
            if player.skipped
            else "no message falls in the time chosen"
        )
        msg = f"nothing played: {why}"
        raise BagError(msg)
    return 0


class _PlayBar:
    """rosbag play's status line, as a progress bar."""

    def __init__(self) -> None:
        self.bar: ProgressBar | None = None
        self._last = 0.0

    def __call__(self, p: PlayProgress) -> None:
        bar = self.bar
        if bar is None or not bar.enabled:
            return
        now = time.monotonic()
        if now - self._last < 0.05 and p.done_s < p.total_s:
            return
        self._last = now
        status = f"Bag Time: {p.bag_ns / 1e9:13.6f}   Duration: {p.done_s:.6f} / {p.total_s:.6f}"
        bar.update(p.done_s, status, "[PAUSED] " if p.paused else "[RUNNING]")


def _wait_before_playing(player: Player, delay: float, wait_subscribers: bool, quiet: bool) -> None:
    """rosbag's pause after advertising (so subscribers can connect), and its optional wait
    for a subscriber on every topic."""
    if wait_subscribers:
        if not quiet:
            logger.info("Waiting for subscribers.")
        while not all(p.wanted for p in player.publishers):
            time.sleep(0.05)
    if delay > 0:
        if not quiet:
            logger.info("Waiting %g seconds after advertising topics...", delay)
        time.sleep(delay)


class _Keys:
    """Space toggles pause, ``s`` steps, as in rosbag play (while stdin is a terminal)."""

    def __init__(self, player: Player) -> None:
        import termios
        import tty

        self._fd = sys.stdin.fileno()
        self._saved = termios.tcgetattr(self._fd)
        tty.setcbreak(self._fd)
        self._player = player
        self._thread = threading.Thread(target=self._read, daemon=True)
        self._thread.start()
        logger.info("Hit space to toggle paused, or 's' to step.")

    def _read(self) -> None:
        player = self._player
        while True:
            try:
                key = os.read(self._fd, 1)
            except OSError:
                return
            if not key:
                return
            if key == b" ":
                player.post(lambda: player.pause(not player.paused))
            elif key == b"s":
                player.post(player.step)

    def close(self) -> None:
        import termios

        termios.tcsetattr(self._fd, termios.TCSADRAIN, self._saved)


def _keyboard(player: Player) -> _Keys | None:
    try:
        return _Keys(player)
    except (OSError, ImportError):
        return None
