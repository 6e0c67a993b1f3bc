"""Saving the simulated world as Gazebo's ``File > Save World As`` does: the world as it is
now, as an SDF 1.6 ``.world``.

The state is copied on the simulation's thread between two physics steps (every body's pose,
one array copy); the poses are worked out, the file made and written on the caller's thread,
atomically, while the simulation runs on at its pace. World models keep their origin (an
``<include>`` of ``model://`` when they came from the model path); a robot spawned from URDF
is written inline as Gazebo converts it.
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TypeVar

import numpy as np
import numpy.typing as npt

from belvedere.description.meshes import resolve_mesh_path
from belvedere.description.urdf import Mesh, RobotModel
from belvedere.errors import BelvedereError, SourceLocation
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics._builder import RobotBuild
from belvedere.sim.physics._simulation import PhysicsSimulation
from belvedere.world import WorldModel, WorldState, robot_entry, write_world
from belvedere.world._poses import from_matrix, matrix
from belvedere.world._writer import Courtesy

__all__ = ["SNAPSHOT_TIMEOUT_S", "WorldSnapshot", "save_world", "snapshot"]

Matrix4 = npt.NDArray[np.float64]
T = TypeVar("T")

SNAPSHOT_TIMEOUT_S = 30.0
"""How long a save waits for the simulation's thread to copy the state."""


@dataclass(frozen=True)
class _Robot:
    name: str
    model: RobotModel
    build: RobotBuild
    packages: PackageIndex | None


@dataclass(frozen=True)
class WorldSnapshot:
    """The world at one instant: its models and robots, every body's pose, the time."""

    world: WorldModel
    """The loaded world with the models added since, without those deleted."""
    roots: dict[str, str]
    """World model → its root body (``world``: welded, where the world file put it)."""
    robots: tuple[_Robot, ...]
    body_ids: dict[str, int]
    xpos: npt.NDArray[np.float64]
    """(nbody, 3): each body's position in the world."""
    xmat: npt.NDArray[np.float64]
    """(nbody, 9): each body's orientation in the world, row-major."""
    state: WorldState

    def body_pose(self, body: str) -> Matrix4:
        i = self.body_ids[body]
        pose = np.eye(4)
        pose[:3, :3] = self.xmat[i].reshape(3, 3)
        pose[:3, 3] = self.xpos[i]
        return pose

    def world_model(self) -> WorldModel:
        """The world as it was, the robots in it as SDF models (Gazebo's conversion)."""
        models = []
        courtesy = Courtesy()
        for entry in self.world.models:
            root = self.roots.get(entry.name, "world")
            if root != "world" and entry.links:
                world_from_model = self.body_pose(root) @ np.linalg.inv(matrix(entry.links[0].pose))
                entry = replace(entry, pose=from_matrix(world_from_model))
            models.append(entry)
            courtesy()
        for robot in self.robots:
            links = {
                link: self.body_pose(body) @ offset
                for link, (body, offset) in robot.build.link_body.items()
            }
            world_from_root = links[robot.model.root_link.name]
            root_from_world = np.linalg.inv(world_from_root)
            models.append(
                robot_entry(
                    robot.model,
                    name=robot.name,
                    pose=from_matrix(world_from_root),
                    link_poses={k: root_from_world @ v for k, v in links.items()},
                    mesh_path=_mesh_path(robot.model, robot.packages),
                )
            )
        return replace(self.world, models=tuple(models))


def _mesh_path(
    model: RobotModel, packages: PackageIndex | None
) -> Callable[[Mesh, SourceLocation | None], Path]:
    def resolve(mesh: Mesh, at: SourceLocation | None) -> Path:
        return resolve_mesh_path(
            mesh.filename, relative_to=model.path, packages=packages, requested_at=at
        )

    return resolve


def snapshot(sim: PhysicsSimulation) -> WorldSnapshot:
    """Copy what a saved world needs: references to the (immutable) models and the bodies'
    poses, tens of microseconds (call on the simulation's thread, between steps)."""
    engine = sim.engine
    roots = dict(sim.world_roots)
    robots = tuple(_Robot(n, r.model, r.build, r.packages) for n, r in sim.robots.items())
    bodies = [root for root in roots.values() if root != "world"]
    bodies += [body for r in robots for body, _ in r.build.link_body.values()]
    return WorldSnapshot(
        world=sim.world,
        roots=roots,
        robots=robots,
        body_ids={body: engine.body_id(body) for body in bodies},
        xpos=engine.d.xpos.copy(),
        xmat=engine.d.xmat.copy(),
        state=WorldState(
            sim_time_ns=sim.graph.now_ns(), wall_time_ns=time.time_ns(), iterations=sim.steps
        ),
    )


def save_world(
    sim: PhysicsSimulation,
    path: str | os.PathLike[str],
    *,
    timeout: float = SNAPSHOT_TIMEOUT_S,
    wait_for_start: bool = False,
) -> Path:
    """Write the simulation's world as it is now to ``path`` (``~`` expanded), whole or not at
    all. Returns the file written (absolute).

    Raises:
        BelvedereError: no path, or the simulation did not answer; FileWriteError: the file
            cannot be written (what was there is unchanged).

    ``wait_for_start``: if the simulation's executor has not started, wait for it to take the
    snapshot (rather than take it here).
    """
    text = os.fspath(path).strip()
    if not text:
        msg = "save world: give the path of the .world file to write"
        raise BelvedereError(msg)
    target = Path(os.path.expanduser(text))
    shot = _on_sim_thread(sim.graph, lambda: snapshot(sim), timeout, wait_for_start)
    return write_world(target, shot.world_model(), shot.state)


def _on_sim_thread(graph: Graph, fn: Callable[[], T], timeout: float, wait_for_start: bool) -> T:
    """``fn()`` on the executor's thread, between callbacks; here when this is that thread,
    the executor has stopped, or it has not started and ``wait_for_start`` is false (a
    service call from another process, which may come while the world is being built on the
    thread that will run the executor, waits for it to start)."""
    executor = graph.executor
    thread = executor.thread
    if thread is threading.current_thread() or executor.stopped:
        return fn()
    if thread is None and not wait_for_start:
        return fn()
    if thread is not None and not thread.is_alive():
        return fn()
    try:
        return executor.call(fn, timeout)
    except TimeoutError:
        msg = f"the simulation did not answer within {timeout:g} s; nothing was saved"
        raise BelvedereError(msg) from None
