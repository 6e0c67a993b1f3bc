"""``belvedere slam BAG --trajectory OUT.tum -o MAP_PREFIX [name:=value …]``: run the SLAM node
offline over a bag, as fast as the CPU allows.

The bag's ``/tf`` and ``/tf_static`` fill a TF buffer as they come; each scan waits, as the
node's message filter makes it, until the odometry at its stamp is known. Writes the map in
map_server's format (``MAP_PREFIX.pgm`` + ``MAP_PREFIX.yaml``, as map_saver writes them) and the
base's trajectory in the map frame, one line per processed scan, in the TUM format
(``stamp tx ty tz qx qy qz qw``). ``name:=value`` set the node's parameters.

The bag is streamed (a progress bar on a terminal). Scans and odometry it cannot use (see
:mod:`belvedere.nav._input`) are told once per cause at the end, counted and naming the bag
and topic; when no scan could be used at all, the error says why.
"""

from __future__ import annotations

import argparse
import logging
import math
import time
from collections import deque
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Protocol

import numpy as np
import numpy.typing as npt

from belvedere.bags import Decoder, ProgressBar, open_bag, wants_progress
from belvedere.cli._args import mappings_only
from belvedere.errors import BelvedereError
from belvedere.fileio import stage_write
from belvedere.graph import NS
from belvedere.maps import OccupancyMap, format_tum_line, save_map
from belvedere.nav._input import Tally
from belvedere.nodes._slam import Processed
from belvedere.nodes.gmapping import GMappingCore, LaserMountError
from belvedere.nodes.hector_mapping import HectorCore
from belvedere.tf import TFBuffer, TFError

logger = logging.getLogger("belvedere.cli")

__all__ = ["add_parser", "run", "tum_text"]

_QUEUE = 5

_NODES = {"gmapping": "slam_gmapping", "hector": "hector_mapping"}


class _Core(Protocol):
    """What GMappingCore and HectorCore offer a run over a bag."""

    base_frame: str
    odom_frame: str
    processed: list[Processed]
    tally: Tally

    @property
    def throttle_scans(self) -> int: ...
    def wanted(self) -> bool: ...
    def ready(self, scan: Any, buffer: TFBuffer) -> bool: ...
    def process(self, scan: Any, buffer: TFBuffer) -> Processed | None: ...
    def occupancy(self) -> OccupancyMap | None: ...
    def trajectory(self) -> tuple[list[int], npt.NDArray[np.float64]]: ...
    def summary(self) -> str: ...


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "slam",
        parents=[common],
        help="build a map from a bag (offline SLAM)",
        description="Run SLAM over a bag's laser scans and odometry (TF), as fast as the CPU "
        "allows; write the map (map_server's format) and the trajectory (TUM). Arguments "
        "name:=value set the node's parameters (slam_gmapping's names).",
    )
    p.add_argument("bag", metavar="BAG", help="a ROS 1 bag or MCAP file (or a ROS 2 bag directory)")
    p.add_argument(
        "--trajectory",
        metavar="OUT.tum",
        help="write the base's poses in the map frame, one line per processed scan",
    )
    p.add_argument(
        "-o",
        "--output",
        metavar="MAP_PREFIX",
        help="write the map as MAP_PREFIX.pgm and MAP_PREFIX.yaml",
    )
    p.add_argument(
        "--algorithm",
        choices=("gmapping", "hector"),
        default="gmapping",
        help="which node to run (default: gmapping)",
    )
    p.add_argument("--scan-topic", default="/scan", help="the LaserScan topic (default: /scan)")
    p.add_argument("--base-frame", default=None, help="the base frame (default: base_link)")
    p.add_argument("--odom-frame", default=None, help="the odometry frame (default: odom)")
    p.set_defaults(run=run)


def _parameters(args: argparse.Namespace) -> dict[str, Any]:
    mappings = mappings_only(list(args.extra))
    names = GMappingCore.names() if args.algorithm == "gmapping" else HectorCore.names()
    known = set(names)
    params: dict[str, Any] = {}
    for name, text in mappings.items():
        key = name.removeprefix("_").removeprefix("~")
        if key not in known:
            message = f"unknown parameter {name!r} for {_NODES[args.algorithm]}"
            raise BelvedereError(message, hint="its parameters: " + ", ".join(sorted(known)))
        params[key] = text
    if args.base_frame is not None:
        params["base_frame"] = args.base_frame
    if args.odom_frame is not None:
        params["odom_frame"] = args.odom_frame
    return params


class _Source(Protocol):
    """A bag's messages, as the run reads them."""

    def counts(self) -> dict[str, int]:
        """Messages per topic."""
        ...

    def messages(self, topics: set[str]) -> Iterator[tuple[str, Any]]:
        """(topic, message) of ``topics`` in time order."""
        ...

    def close(self) -> None: ...


class _BagSource:
    """A ROS 1 bag or an MCAP file, read by belvedere (every length checked, a damaged
    chunk skipped with a warning); a message that cannot be decoded is skipped, counted."""

    def __init__(self, path: str) -> None:
        self.bag = open_bag(path)
        self.decoder = Decoder()
        self.undecodable: dict[str, int] = {}

    def counts(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for c in self.bag.connections:
            out[c.topic] = out.get(c.topic, 0) + self.bag.counts.get(c.id, 0)
        return out

    def messages(self, topics: set[str]) -> Iterator[tuple[str, Any]]:
        decoder = self.decoder
        where = str(self.bag.path)
        chosen = [c for c in self.bag.connections if c.topic in topics and decoder.usable(c, where)]
        for m in self.bag.messages(chosen):
            try:
                msg = decoder.decode(m)
            except Exception as err:  # noqa: BLE001 (a damaged message: skip it, counted)
                topic = m.connection.topic
                self.undecodable[topic] = self.undecodable.get(topic, 0) + 1
                if self.undecodable[topic] == 1:
                    logger.warning(
                        "%s: skipping a message on %s: it cannot be decoded (%s)",
                        self.bag.path,
                        topic,
                        _first_line(err),
                    )
                continue
            yield m.connection.topic, msg

    def close(self) -> None:
        self.bag.close()
        for topic, n in sorted(self.undecodable.items()):
            if n > 1:
                logger.warning("skipped %d messages on %s that could not be decoded", n, topic)


class _Ros2Source:
    """A ROS 2 bag directory, read by rosbags."""

    def __init__(self, path: str) -> None:
        from rosbags.highlevel import AnyReader  # only ROS 2 bag directories need it

        self.path = path
        try:
            self.reader = AnyReader([Path(path)])
            self.reader.open()
        except Exception as err:  # noqa: BLE001 - rosbags raises several kinds for a bad bag
            message = f"{path}: not a ROS 2 bag rosbags can read ({_first_line(err)})"
            raise BelvedereError(message) from None

    def counts(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for c in self.reader.connections:
            out[c.topic] = out.get(c.topic, 0) + c.msgcount
        return out

    def messages(self, topics: set[str]) -> Iterator[tuple[str, Any]]:
        reader = self.reader
        wanted = [c for c in reader.connections if c.topic in topics]
        try:
            for connection, _, raw in reader.messages(connections=wanted):
                yield connection.topic, reader.deserialize(raw, connection.msgtype)
        except Exception as err:  # noqa: BLE001 - rosbags raises several kinds for a bad bag
            message = f"{self.path}: cannot read on ({_first_line(err)})"
            raise BelvedereError(message) from None

    def close(self) -> None:
        self.reader.close()


def _first_line(err: BaseException) -> str:
    text = (str(err).strip().splitlines() or [type(err).__name__])[0]
    return text if len(text) <= 120 else text[:117] + "..."


def _open_bag(path: str) -> _Source:
    """The bag at ``path``: a ROS 1 bag or MCAP file, or a ROS 2 bag directory."""
    if not Path(path).exists():
        message = f"{path}: no such bag"
        raise BelvedereError(message)
    if Path(path).is_dir():
        return _Ros2Source(path)
    return _BagSource(path)


def _messages(reader: _Source, scan_topic: str) -> tuple[Iterator[tuple[str, Any]], int]:
    """(topic, message) in the bag's order for the scan and TF topics, and how many scans."""
    counts = reader.counts()
    if scan_topic not in counts:
        message = f"the bag has no topic {scan_topic}"
        hint = "its topics: " + ", ".join(sorted(counts)) if counts else "it has no topics"
        raise BelvedereError(message, hint=hint)
    messages = reader.messages({scan_topic, "/tf", "/tf_static"})
    return messages, counts[scan_topic]


def tum_text(stamps_ns: list[int], poses: Any) -> str:
    """TUM trajectory text: ``stamp tx ty tz qx qy qz qw`` per pose (x, y, yaw)."""
    return "".join(
        format_tum_line(
            ns / NS, (float(x), float(y), 0.0), (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
        )
        for ns, (x, y, yaw) in zip(stamps_ns, poses, strict=True)
    )


def run(args: argparse.Namespace) -> int:
    if not args.trajectory and not args.output:
        message = "nothing to write: give --trajectory OUT.tum and/or -o MAP_PREFIX"
        raise BelvedereError(message)
    params = _parameters(args)
    core: _Core
    # What the run leaves out of bad scans and odometry, told once per cause at the end.
    tally = Tally(f"{args.bag}: {args.scan_topic}", logger, live=False)
    try:
        if args.algorithm == "gmapping":
            core = gmapping = GMappingCore(params, tally=tally)
            if gmapping.without_effect is not None:
                logger.warning("slam_gmapping: %s", gmapping.without_effect)
        else:
            core = HectorCore(params, tally=tally)
    except ValueError as err:
        raise BelvedereError(str(err)) from None
    reader = _open_bag(args.bag)
    started = time.perf_counter()
    try:
        messages, total = _messages(reader, args.scan_topic)
        total = -(-total // core.throttle_scans)
        bar = ProgressBar("slam (scans)", total, enabled=wants_progress(args.quiet > 0))
        buffer = TFBuffer(cache_time=3600.0)
        pending: deque[Any] = deque()
        problems: list[str] = []
        try:
            for topic, msg in messages:
                if topic == "/tf" or topic == "/tf_static":
                    buffer.set_message(msg, static=topic == "/tf_static")
                elif core.wanted():
                    pending.append(msg)
                    if len(pending) > _QUEUE:
                        pending.popleft()
                        problems.append("a scan waited too long for its odometry and was dropped")
                while pending and core.ready(pending[0], buffer):
                    _process(core, pending.popleft(), buffer, problems)
                    if len(core.processed) % 25 == 0:
                        bar.update(len(core.processed), core.summary())
            bar.update(len(core.processed), core.summary())
        finally:
            bar.close()
    finally:
        reader.close()
    for text in sorted(set(problems)):
        logger.warning("warning: %s (%d times)", text, problems.count(text))
    grid = core.occupancy()
    if not core.processed or grid is None:
        message = f"{args.bag}: no scan on {args.scan_topic} could be placed"
        if tally:  # every scan was refused: the reasons are the error's
            raise BelvedereError(message, hint="; ".join(tally.lines(who=False)))
        if core.processed:
            message = f"{args.bag}: no scan on {args.scan_topic} had a usable range"
            hint = "every range was outside range_min..range_max (and the node's own limits)"
            raise BelvedereError(message, hint=hint)
        needs = (
            f"TF from {core.odom_frame} to {core.base_frame} at the scans' stamps"
            if args.algorithm == "gmapping"
            else f"TF from the laser's frame to {core.base_frame}"
        )
        raise BelvedereError(message, hint=f"the bag needs {needs}")
    tally.report()
    if args.trajectory:
        stamps, poses = core.trajectory()
        stage_write(args.trajectory, tum_text(stamps, poses), make_dirs=True).commit()
    if args.output:
        save_map(args.output, grid)
    logger.info(
        "%d scans, %s, %.1f s",
        len(core.processed),
        core.summary(),
        time.perf_counter() - started,
    )
    return 0


def _process(core: _Core, scan: Any, buffer: TFBuffer, problems: list[str]) -> None:
    try:
        core.process(scan, buffer)
    except LaserMountError as err:
        raise BelvedereError(str(err)) from None
    except TFError as err:
        problems.append(f"a scan could not be placed ({err.message})")
    except ValueError as err:
        problems.append(str(err))
