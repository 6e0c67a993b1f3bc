"""gazebo_ros: gzserver (the physics simulation; also ``debug``, gzserver in gdb),
gzclient (the viewer), spawn_model."""

from __future__ import annotations

import logging
import os
import shlex
from pathlib import Path

from belvedere.graph import Node, ServiceUnavailableError
from belvedere.nodes._registry import (
    FileClaim,
    NodeSpec,
    Session,
    Starter,
    StartError,
    end_node,
)
from belvedere.packages import BUILTIN_PACKAGES

__all__ = ["EXECUTABLES", "FILES", "JOINING", "PACKAGE"]

PACKAGE = "gazebo_ros"

logger = logging.getLogger(__name__)


def _gzserver(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.sim.physics import GazeboRos, PhysicsSimulation
    from belvedere.world import empty_world, read_world

    paused = "-u" in shlex.split(spec.args)
    world = empty_world()
    path = _world_path(spec)
    if path is not None:
        world = read_world(path, packages=session.packages)
        for warning in world.warnings:
            logger.warning("%s", warning)
    session.sim = PhysicsSimulation(session.graph, world, node=node)
    GazeboRos(session.sim, packages=session.packages)
    if paused:
        session.graph.executor.pause(True)


def _world_path(spec: NodeSpec) -> Path | None:
    """The world gzserver's arguments name (its last word that is not an option or a physics
    engine), found as Gazebo finds it: as given, else along ``GAZEBO_RESOURCE_PATH``, else
    among the worlds belvedere provides."""
    words = shlex.split(spec.args)
    files = [
        w for w in words if not w.startswith("-") and w not in ("ode", "bullet", "dart", "simbody")
    ]
    if not files:
        return None
    path = Path(files[-1])
    if not path.is_absolute() and not os.path.exists(path):
        resource = os.environ.get("GAZEBO_RESOURCE_PATH", "")
        candidates = [Path(d) / path for d in resource.split(":") if d]
        candidates.append(BUILTIN_PACKAGES / "gazebo_ros" / path)
        path = next((c for c in candidates if os.path.isfile(c)), path)
    return path


def _world_files(spec: NodeSpec) -> list[tuple[str, str]]:
    path = _world_path(spec)
    return [] if path is None else [("world", str(path))]


def _gzclient(session: Session, spec: NodeSpec, node: Node) -> None:
    session.want_viewer = True


def _spawn_model(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.sim.physics import parse_spawn_args, spawn_model

    def spawn() -> None:
        words = shlex.split(spec.args)
        if session.sim is None:
            _spawn_elsewhere(session, spec, node, words)
            return
        name = parse_spawn_args(words).model
        _check_spawn_name(session, spec, name)
        spawn_model(node, words)
        session.spawned[name] = spec
        end_node(session, node, 0)  # spawn_model exits once the model is in

    session.deferred.append(spawn)


def _spawn_elsewhere(session: Session, spec: NodeSpec, node: Node, words: list[str]) -> None:
    """``rosrun gazebo_ros spawn_model …`` beside a simulation another process runs: through
    its ``spawn_*_model`` service (which refuses a name the world has, as Gazebo's does), and
    the node ends, as spawn_model exits once the model is in."""
    from belvedere.sim.physics import spawn_model

    try:
        spawn_model(node, words)
    except ServiceUnavailableError:
        msg = (
            "spawn_model: no simulation is running (start one first, e.g. "
            "roslaunch gazebo_ros empty_world.launch, or include it in this launch)"
        )
        raise StartError(msg, spec.source) from None
    end_node(session, node, 0)


def _check_spawn_name(session: Session, spec: NodeSpec, name: str) -> None:
    """Gazebo refuses to spawn a model under a name the world already has (a world saved
    with the robot in it, then launched with its spawner): its words, and both places."""
    from belvedere.sim.physics import name_taken

    earlier = session.spawned.get(name)
    if earlier is not None:
        msg = (
            f"spawn_model -model {name}: {name_taken(name)} ({earlier.full_name}, at "
            f"{earlier.source}, spawned a model of that name)"
        )
        raise StartError(msg, spec.source, hint="give each spawn_model its own -model name")
    entry = session.sim.world_entry(name)
    if entry is not None:
        where = entry.source or session.sim.world.path or "the world"
        msg = (
            f"spawn_model -model {name}: {name_taken(name)} (the world already has a model "
            f"named {name!r}, at {where})"
        )
        raise StartError(
            msg,
            spec.source,
            hint="a world saved while the robot was in it keeps the robot, and it runs as it "
            "did: drop this spawner, or that <model> from the world file, or spawn under "
            "another -model name",
        )


EXECUTABLES: dict[str, Starter] = {
    "gzserver": _gzserver,
    "debug": _gzserver,  # empty_world.launch's debug:=true (gzserver in gdb)
    "gzclient": _gzclient,
    "spawn_model": _spawn_model,
}
FILES: dict[str, FileClaim] = {"gzserver": _world_files, "debug": _world_files}
JOINING = frozenset({"spawn_model"})
"""``run gazebo_ros spawn_model …`` (or a launch of spawners only) joins the simulation that
runs, as the spawner of ``rosrun`` finds Gazebo's services through the master."""
