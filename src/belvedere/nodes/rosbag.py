"""rosbag: ``record`` and ``play`` as nodes, with rosbag's arguments.

Both run in this process on the session's graph. ``record`` subscribes once every node of
the launch exists (and to topics that appear later, with ``-a`` or ``-e``), stamps each
message with the graph's time, and closes its bag when the session ends (or when its
``--duration``, ``--size`` or ``--limit`` is reached; a ``required`` recorder then ends the
session). ``play`` lays the bag on the graph's time from the start (``--clock``: the graph's
time is the bag's, and the graph announces it on ``/clock``), so a launch that plays a bag
into other nodes gives the same result at any ``--rtf``; it ends with the bag (a
``required`` player ends the session). Relative file names are relative to the directory
belvedere runs in (ROS 1 puts them in ``~/.ros``); rosbag's ``--delay`` is not needed here:
every subscriber exists before playing starts.
"""

from __future__ import annotations

import logging
import shlex
from pathlib import Path

from belvedere.bags import (
    BagError,
    GraphRecording,
    Player,
    Recorder,
    parse_play_args,
    parse_record_args,
)
from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter, StartError, end_when

__all__ = ["ANONYMOUS", "EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "rosbag"

logger = logging.getLogger("belvedere.launch")


def _record(session: Session, spec: NodeSpec, node: Node) -> None:
    try:
        options = parse_record_args(shlex.split(spec.args))
    except BagError as err:
        raise StartError(err.message, spec.source, hint=err.hint) from None
    recorder = Recorder(options, directory=Path.cwd())

    def start() -> None:
        try:
            recorder.start(GraphRecording(node, recorder))
        except BagError as err:
            raise StartError(err.message, spec.source, hint=err.hint) from None
        session.closers.append(recorder.stop)

    session.deferred.append(start)
    end_when(session, node, recorder.finished.is_set)


def _play(session: Session, spec: NodeSpec, node: Node) -> None:
    try:
        options = parse_play_args(shlex.split(spec.args))
        player = Player(node, options)
    except BagError as err:
        raise StartError(err.message, spec.source, hint=err.hint) from None
    if options.clock and options.rate != 1.0:
        logger.warning(
            "%s: with --clock the launch's --rtf paces the bag's time; -r %g is not used",
            spec.source,
            options.rate,
        )
    session.closers.append(player.close)
    session.deferred.append(player.start)
    end_when(session, node, player.done.is_set)


EXECUTABLES: dict[str, Starter] = {"record": _record, "play": _play}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset({"record", "play"})
"""Named as roscpp's ``AnonymousName`` names it when run without ``__name:=``."""
