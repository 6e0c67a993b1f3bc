"""map_server: ``map_server`` serves a map file, ``map_saver`` writes the map it receives.

``map_server MAP.yaml`` (or the old ``map_server IMAGE RESOLUTION``) publishes the map latched
on ``map`` and its ``nav_msgs/MapMetaData`` on ``map_metadata``, and answers ``static_map``
(``nav_msgs/GetMap``); ``~frame_id`` names the map's frame. As map_server, it stamps the map
when time is valid (in simulated time, once the clock has left zero).

``map_saver [-f NAME] [--occ T] [--free T]`` waits for one map on ``map`` (remappable), writes
``NAME.pgm`` and ``NAME.yaml`` byte for byte as map_saver does, and ends. One that cannot
write says so as map_saver does and ends with status 1 (map_saver would wait for another map,
which a latched topic never sends).
"""

from __future__ import annotations

import re
import shlex
import sys
from typing import Any

from belvedere.fileio import FileWriteError
from belvedere.graph import Node
from belvedere.maps import (
    DEFAULT_SAVE_FREE,
    DEFAULT_SAVE_OCCUPIED,
    MapError,
    OccupancyMap,
    grid_message,
    load_image_map,
    map_from_message,
    metadata_message,
    read_map_yaml,
    save_map,
)
from belvedere.msgs import types
from belvedere.nodes._registry import (
    FileClaim,
    NodeSpec,
    Session,
    Starter,
    StartError,
    end_node,
)

__all__ = ["EXECUTABLES", "FILES", "JOINING", "PACKAGE", "SAVER_USAGE", "SERVER_USAGE"]

PACKAGE = "map_server"

SERVER_USAGE = (
    "\nUSAGE: map_server <map.yaml>\n"
    "  map.yaml: map description file\n"
    "DEPRECATED USAGE: map_server <map> <resolution>\n"
    "  map: image file to load\n"
    "  resolution: map resolution [meters/pixel]"
)
SAVER_USAGE = (
    "Usage: \n"
    "  map_saver -h\n"
    "  map_saver [--occ <threshold_occupied>] [--free <threshold_free>] [-f <mapname>] "
    "[ROS remapping args]"
)


def _atoi(text: str) -> int:
    """C's ``atoi``: the leading integer of ``text``, 0 if there is none."""
    found = re.match(r"\s*([+-]?\d+)", text)
    return int(found.group(1)) if found else 0


def _atof(text: str) -> float | None:
    """The leading number of ``text`` as C's ``atof`` reads it (None if there is none)."""
    found = re.match(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)", text)
    return float(found.group(1)) if found else None


# --- map_server ------------------------------------------------------------------------------
def _load(spec: NodeSpec, node: Node, argv: list[str]) -> tuple[OccupancyMap, str]:
    """The map the arguments name (the YAML form, or the old image + resolution form), and
    its image's path."""
    if len(argv) not in (1, 2):
        msg = f"map_server takes a map file, got {len(argv)} arguments: {shlex.join(argv)!r}"
        raise StartError(msg, spec.source, hint=SERVER_USAGE.strip())
    try:
        if len(argv) == 1:
            meta = read_map_yaml(argv[0])
            node.logger.info('Loading map from image "%s"', meta.image)
            return meta.load(), str(meta.image)
        node.logger.warning(
            "Using deprecated map server interface. Please switch to new interface."
        )
        resolution = _atof(argv[1])
        if resolution is None or not resolution > 0:
            msg = f"map_server {argv[0]} {argv[1]}: the resolution must be a positive number"
            raise StartError(msg, spec.source, hint=SERVER_USAGE.strip())
        node.logger.info('Loading map from image "%s"', argv[0])
        grid = load_image_map(
            argv[0],
            resolution,
            negate=bool(node.get_param("~negate", 0)),
            occupied_thresh=float(node.get_param("~occupied_thresh", 0.65)),
            free_thresh=float(node.get_param("~free_thresh", 0.196)),
        )
        return grid, argv[0]
    except MapError as err:
        error = StartError(err.message, err.location, hint=err.hint, trail=err.trail)
        if spec.source is not None:
            error.add_trail(f"loading the map of node {spec.full_name} at", spec.source)
        raise error from None


class _MapServer:
    """Publishes one map (latched) and answers ``static_map`` with it."""

    def __init__(self, node: Node, grid: OccupancyMap) -> None:
        self.node = node
        self.grid = grid
        self.frame_id = str(node.get_param("~frame_id", "map"))
        node.service("static_map", "nav_msgs/GetMap", self._on_get_map)
        self.metadata_pub = node.publisher(
            "map_metadata", "nav_msgs/MapMetaData", latch=True, queue_size=1
        )
        self.map_pub = node.publisher("map", "nav_msgs/OccupancyGrid", latch=True, queue_size=1)
        self.message = grid_message(grid, frame_id=self.frame_id)
        node.logger.info(
            "Read a %d X %d map @ %.3f m/cell", grid.width, grid.height, grid.resolution
        )
        if node.graph.sim_time and node.now_ns() == 0:
            # map_server waits for valid time (a simulated clock that has left zero) so the
            # map's stamp means something; the first moment after zero is the first it can.
            node.timer(1e-9, self._publish, oneshot=True)
        else:
            self._publish()

    def _publish(self) -> None:
        now = self.node.now_ns()
        self.message = grid_message(
            self.grid, frame_id=self.frame_id, stamp_ns=now, load_time_ns=now
        )
        self.metadata_pub.publish(metadata_message(self.grid, now))
        self.map_pub.publish(self.message)

    def _on_get_map(self, request: Any) -> Any:
        self.node.logger.info("Sending map")
        return types().cls("nav_msgs/srv/GetMap_Response")(self.message)


def _server_files(spec: NodeSpec) -> list[tuple[str, str]]:
    """The map's YAML and the image it names (or the old form's image)."""
    argv = shlex.split(spec.args)
    if len(argv) == 2:
        return [("image", argv[0])]
    if len(argv) != 1:
        return []
    try:
        image = str(read_map_yaml(argv[0]).image)
    except MapError:  # the start says what is wrong with it
        return [("map", argv[0])]
    return [("map", argv[0]), ("image", image)]


def _start_server(session: Session, spec: NodeSpec, node: Node) -> None:
    grid, _ = _load(spec, node, shlex.split(spec.args))
    _MapServer(node, grid)


# --- map_saver -------------------------------------------------------------------------------
def _saver_args(spec: NodeSpec) -> tuple[str, int, int] | None:
    """(name, occupied, free) from map_saver's arguments; None for ``-h``."""
    argv = shlex.split(spec.args)
    name, occupied, free = "map", DEFAULT_SAVE_OCCUPIED, DEFAULT_SAVE_FREE
    hint = SAVER_USAGE.replace("Usage: \n  ", "usage: ").replace("\n  ", " or ")
    i = 0
    while i < len(argv):
        word = argv[i]
        if word == "-h":
            return None
        if word in ("-f", "--occ", "--free"):
            if i + 1 >= len(argv):
                msg = f"map_saver: {word} needs a value"
                raise StartError(msg, spec.source, hint=hint)
            value = argv[i + 1]
            i += 2
            if word == "-f":
                name = value
            elif word == "--occ":
                occupied = _atoi(value)
                if not 1 <= occupied <= 100:
                    msg = f"map_saver: threshold_occupied must be between 1 and 100 (got {value!r})"
                    raise StartError(msg, spec.source)
            else:
                free = _atoi(value)
                if not 0 <= free <= 100:
                    msg = f"map_saver: threshold_free must be between 0 and 100 (got {value!r})"
                    raise StartError(msg, spec.source)
            continue
        msg = f"map_saver: unknown argument {word!r}"
        raise StartError(msg, spec.source, hint=hint)
    if occupied <= free:
        msg = (
            "map_saver: threshold_free must be smaller than threshold_occupied "
            f"(--free {free}, --occ {occupied})"
        )
        raise StartError(msg, spec.source)
    return name, occupied, free


def _start_saver(session: Session, spec: NodeSpec, node: Node) -> None:
    parsed = _saver_args(spec)
    if parsed is None:
        sys.stdout.write(SAVER_USAGE + "\n")
        end_node(session, node, 0)
        return
    name, occupied, free = parsed
    log = node.logger

    def on_map(msg: Any) -> None:
        if node.closed:
            return
        log.info(
            "Received a %d X %d map @ %.3f m/pix",
            msg.info.width,
            msg.info.height,
            msg.info.resolution,
        )
        try:
            grid = map_from_message(msg)
        except ValueError as err:
            log.error("Couldn't save the map: %s", err)
            end_node(session, node, 1)
            return
        log.info("Writing map occupancy data to %s", f"{name}.pgm")
        log.info("Writing map occupancy data to %s", f"{name}.yaml")
        try:
            save_map(name, grid, occupied=occupied, free=free)
        except FileWriteError as err:
            log.error("Couldn't save map file to %s: %s", err.path, err.reason)
            end_node(session, node, 1)
            return
        log.info("Done")
        end_node(session, node, 0)

    log.info("Waiting for the map")
    node.subscribe("map", "nav_msgs/OccupancyGrid", on_map, queue_size=1)


EXECUTABLES: dict[str, Starter] = {"map_server": _start_server, "map_saver": _start_saver}
FILES: dict[str, FileClaim] = {"map_server": _server_files}
JOINING = frozenset(EXECUTABLES)
"""Both join a graph that is already running when ``run`` starts them (``rosrun map_server
map_saver -f mymap`` while gmapping runs)."""
