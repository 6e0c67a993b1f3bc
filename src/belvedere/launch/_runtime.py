"""Running a :class:`LaunchConfig` on one graph: the parameters set, every node started.

Nodes are found in a registry by ROS package and type and run in this process; a Python
script from the user's own package runs as a subprocess. A node type belvedere does not have
is one line naming it; the rest of the launch runs. ``spawn_model`` and ``controller_manager
spawner`` run once everything else exists, as they would wait for the services they call.
"""

from __future__ import annotations

import logging
import os
import shlex
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from belvedere.description.urdf import RobotModel
from belvedere.errors import BelvedereError
from belvedere.fileio import FileWriteError, write_file
from belvedere.graph import Graph, Node, ZenohTransport
from belvedere.launch._model import LaunchConfig, LaunchError, LaunchNode
from belvedere.msgs import types
from belvedere.packages import BUILTIN_PACKAGES, PackageIndex
from belvedere.tf import JointStatePublisher, RobotStatePublisher, static_transform_publisher

__all__ = ["NODE_TYPES", "LaunchRuntime"]

logger = logging.getLogger("belvedere.launch")

Starter = Callable[["LaunchRuntime", LaunchNode, Node], None]


@dataclass
class LaunchRuntime:
    """The running launch: its graph, simulation, viewer and subprocesses."""

    config: LaunchConfig
    graph: Graph
    packages: PackageIndex
    headless: bool = False
    viewer_options: dict[str, Any] = field(default_factory=dict)
    sim: Any = None
    viewer: Any = None
    joint_publisher: JointStatePublisher | None = None
    gui_joints: bool = False
    rviz_config: str | None = None
    want_viewer: bool = False
    world: Any = None
    processes: list[tuple[LaunchNode, subprocess.Popen[bytes]]] = field(default_factory=list)
    deferred: list[Callable[[], None]] = field(default_factory=list)
    """Run after every node exists (spawn_model)."""
    controllers: list[Callable[[], None]] = field(default_factory=list)
    """Run after that (controller spawners: the robots they control exist by then)."""
    missing: list[str] = field(default_factory=list)
    spawned: dict[str, LaunchNode] = field(default_factory=dict)
    """Model name → the spawn_model node that spawned it."""
    respawn_at: dict[int, float] = field(default_factory=dict)

    def start(self) -> None:
        params = self.graph.params
        for ns in self.config.clear:
            if params.has(ns):
                params.delete(ns)
        for name in self.config.deletions:
            if params.has(name):
                params.delete(name)
        for name, param in self.config.params.items():
            params.set(name, param.value)
        for file, ns in self.config.dumps:
            try:
                write_file(file, params.dump_yaml(ns) if params.has(ns) or ns == "/" else "")
            except FileWriteError as err:
                logger.warning("rosparam dump: %s", err.message)
        for spec in self.config.nodes:
            self._start(spec)
        for action in [*self.deferred, *self.controllers]:
            action()
        if self.missing:
            logger.warning(
                "not started (belvedere has no such node yet): %s; the rest of the launch runs",
                ", ".join(self.missing),
            )
        if self.want_viewer and not self.headless:
            self._open_viewer()

    def _start(self, spec: LaunchNode) -> None:
        starter = NODE_TYPES.get((spec.pkg, spec.type))
        if starter is None:
            script = self._user_script(spec)
            if script is not None:
                self._run_script(spec, script)
                return
            self.missing.append(f"{spec.pkg}/{spec.type} ({spec.full_name}, {spec.source})")
            return
        node = self.graph.create_node(
            spec.name, namespace=spec.namespace, remappings=dict(spec.remappings)
        )
        starter(self, spec, node)

    # --- user scripts ------------------------------------------------------------------------
    def _user_script(self, spec: LaunchNode) -> Path | None:
        try:
            root = self.packages.find(spec.pkg, requested_at=spec.source)
        except BelvedereError:
            return None
        if root.is_relative_to(BUILTIN_PACKAGES):
            return None
        for candidate in (
            root / "scripts" / spec.type,
            root / "nodes" / spec.type,
            root / spec.type,
        ):
            if os.path.isfile(candidate):
                return candidate
        return next(iter(sorted(root.rglob(spec.type))), None)

    def _graph_env(self) -> dict[str, str]:
        """What a script node needs to join this launch's graph (its domain and endpoint)."""
        transport = self.graph.transport
        if not isinstance(transport, ZenohTransport):
            return {}
        return {
            "BELVEDERE_DOMAIN": str(transport.domain),
            "BELVEDERE_ENDPOINT": transport.endpoint,
        }

    def _run_script(self, spec: LaunchNode, script: Path) -> None:
        text = script.read_text(errors="replace")
        if "import rospy" in text or "from rospy" in text:
            logger.warning(
                "%s: %s imports rospy: rospy scripts are not supported yet; not started",
                spec.source,
                script,
            )
            return
        env = {**os.environ, **self._graph_env(), **dict(spec.env)}
        argv = [sys.executable, str(script), *shlex.split(spec.args)]
        argv.append(f"__name:={spec.name}")
        if spec.namespace != "/":
            argv.append(f"__ns:={spec.namespace}")
        argv += [f"{a}:={b}" for a, b in spec.remappings]
        output = None if spec.output == "screen" else subprocess.DEVNULL
        process = subprocess.Popen(argv, env=env, cwd=spec.cwd, stdout=output, stderr=output)
        self.processes.append((spec, process))

    def poll_processes(self) -> LaunchNode | None:
        """A required node that has exited (the launch then ends), if any; nodes with
        ``respawn`` that exited are started again after their ``respawn_delay``."""
        now = time.monotonic()
        for i, (spec, process) in enumerate(list(self.processes)):
            if process.poll() is None:
                continue
            if spec.required:
                return spec
            if spec.respawn:
                due = self.respawn_at.setdefault(id(process), now + spec.respawn_delay)
                if now >= due:
                    logger.info("respawning %s", spec.full_name)
                    self.processes.pop(i)
                    script = self._user_script(spec)
                    if script is not None:
                        self._run_script(spec, script)
                    break
        return None

    # --- the viewer ------------------------------------------------------------------------------
    def _open_viewer(self) -> None:
        from belvedere.viewer import Viewer, read_rviz

        text = self.graph.params.get("/robot_description", None)
        model = RobotModel.from_string(text, path="robot_description") if text else None
        sim = self.sim
        self.viewer = Viewer(
            self.graph,
            model=model,
            rviz=read_rviz(self.rviz_config) if self.rviz_config else None,
            joint_publisher=self.joint_publisher if self.gui_joints else None,
            sim=sim,
            packages=self.packages,
            world=getattr(sim, "world", None),
            world_poses=sim.model_poses if sim is not None else None,
            fixed_frame=None if self.rviz_config else getattr(sim, "odom_frame", None),
            **self.viewer_options,
        )
        if sim is not None and not self.rviz_config:
            for kind, topic in sim.sensor_topics():
                self.viewer.add_display(kind, topic)
        sys.stderr.write(f"viewer: {self.viewer.url}\n")

    def close(self) -> None:
        if self.viewer is not None:
            self.viewer.close()
        for _, process in self.processes:
            if process.poll() is None:
                process.terminate()
                try:
                    process.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    process.kill()


# --- the node types ----------------------------------------------------------------------------


def _robot_state_publisher(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    if spec.type == "state_publisher":
        logger.warning(
            "%s: robot_state_publisher's 'state_publisher' is deprecated; use "
            'type="robot_state_publisher"',
            spec.source,
        )
    RobotStatePublisher(node)


def _joint_state_publisher(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    rt.joint_publisher = JointStatePublisher(node)
    use_gui = node.get_param("use_gui", False) or node.get_param("~use_gui", False)
    if spec.pkg == "joint_state_publisher_gui" or use_gui is True or str(use_gui).lower() == "true":
        rt.gui_joints = True
        rt.want_viewer = True


def _rviz(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    words = shlex.split(spec.args)
    for flag in ("-d", "--display-config"):
        if flag in words and words.index(flag) + 1 < len(words):
            rt.rviz_config = words[words.index(flag) + 1]
    rt.want_viewer = True


def _arbotix(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    from belvedere.sim.kinematic import ArbotixDriver

    ArbotixDriver(node)


def _gzserver(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    from belvedere.sim.physics import GazeboRos, PhysicsSimulation
    from belvedere.world import empty_world, read_world

    words = shlex.split(spec.args)
    paused = "-u" in words
    files = [
        w for w in words if not w.startswith("-") and w not in ("ode", "bullet", "dart", "simbody")
    ]
    world = empty_world()
    if files:
        path = Path(files[-1])
        if not path.is_absolute() and not os.path.exists(path):
            resource = os.environ.get("GAZEBO_RESOURCE_PATH", "")
            candidates = [Path(d) / path for d in resource.split(":") if d]
            candidates.append(BUILTIN_PACKAGES / "gazebo_ros" / path)
            path = next((c for c in candidates if os.path.isfile(c)), path)
        world = read_world(path, packages=rt.packages)
        for warning in world.warnings:
            sys.stderr.write(f"{warning}\n")
    rt.sim = PhysicsSimulation(rt.graph, world, node=node)
    GazeboRos(rt.sim, packages=rt.packages)
    if paused:
        rt.graph.executor.pause(True)


def _gzclient(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    rt.want_viewer = True


def _spawn_model(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    from belvedere.sim.physics import parse_spawn_args, spawn_model

    def spawn() -> None:
        if rt.sim is None:
            msg = "spawn_model: no simulation is running (include gazebo_ros/empty_world.launch)"
            raise LaunchError(msg, spec.source)
        words = shlex.split(spec.args)
        name = parse_spawn_args(words).model
        _check_spawn_name(rt, spec, name)
        spawn_model(node, words)
        rt.spawned[name] = spec

    rt.deferred.append(spawn)


def _check_spawn_name(rt: LaunchRuntime, spec: LaunchNode, name: str) -> None:
    """Gazebo refuses to spawn a model under a name the world already has (a world saved
    with the robot in it, then launched with its spawner): one error naming both places."""
    earlier = rt.spawned.get(name)
    if earlier is not None:
        msg = (
            f"spawn_model -model {name}: {earlier.full_name} (at {earlier.source}) already "
            "spawned a model of that name; Gazebo refuses a second one"
        )
        raise LaunchError(msg, spec.source, hint="give each spawn_model its own -model name")
    entry = rt.sim.world.model(name)
    if entry is not None:
        where = entry.source or rt.sim.world.path or "the world"
        msg = (
            f"spawn_model -model {name}: the world already has a model named {name!r} "
            f"(at {where}); Gazebo refuses to spawn it again"
        )
        raise LaunchError(
            msg,
            spec.source,
            hint="remove that <model> from the world file (a world saved while the robot was "
            "in it keeps a copy), or spawn under another -model name",
        )


def _spawner(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    from belvedere.sim.physics import spawner

    words = shlex.split(spec.args)
    if spec.type == "controller_manager":
        if not words or words[0] not in ("spawn", "load"):
            msg = "controller_manager: expected 'spawn NAME…' or 'load NAME…'"
            raise LaunchError(msg, spec.source)
        words = words[1:] + (["--stopped"] if words[0] == "load" else [])

    def spawn() -> None:
        spawner(node, words, namespace=spec.namespace)

    rt.controllers.append(spawn)


def _static_transform(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    static_transform_publisher(node, shlex.split(spec.args))


def _teleop(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    if not sys.stdin.isatty():
        logger.warning(
            "%s: teleop_twist_keyboard needs a terminal; run 'belvedere teleop' in one",
            spec.source,
        )
        return
    from belvedere.teleop import TwistKeyboard, run_teleop

    pub = node.publisher("cmd_vel", "geometry_msgs/Twist", queue_size=1)
    twist, vector = types().cls("geometry_msgs/Twist"), types().cls("geometry_msgs/Vector3")
    speed = float(node.get_param("~speed", 0.5))
    turn = float(node.get_param("~turn", 1.0))

    def publish(t: tuple[float, float, float, float]) -> None:
        pub.publish(twist(vector(t[0], t[1], t[2]), vector(0.0, 0.0, t[3])))

    thread = threading.Thread(
        target=run_teleop,
        args=(TwistKeyboard(speed, turn), publish, sys.stdin.fileno(), sys.stdout),
        daemon=True,
    )
    thread.start()


class _DepthToScan:
    """depthimage_to_laserscan: the middle rows of a depth image as a LaserScan."""

    def __init__(self, node: Node) -> None:
        self.node = node
        self.scan_height = int(node.get_param("~scan_height", 1))
        self.range_min = float(node.get_param("~range_min", 0.45))
        self.range_max = float(node.get_param("~range_max", 10.0))
        self.frame = str(node.get_param("~output_frame_id", "camera_depth_frame"))
        self.info: Any = None
        self.pub = node.publisher("scan", "sensor_msgs/LaserScan", queue_size=10)
        node.subscribe("camera_info", "sensor_msgs/CameraInfo", self._on_info, queue_size=1)
        node.subscribe("image", "sensor_msgs/Image", self._on_image, queue_size=1)

    def _on_info(self, msg: Any) -> None:
        self.info = msg

    def _on_image(self, msg: Any) -> None:
        if self.info is None:
            return
        fx, cx, cy = float(self.info.K[0]), float(self.info.K[2]), float(self.info.K[5])
        if msg.encoding == "16UC1":
            millimetres = np.asarray(msg.data).view(np.uint16).reshape(msg.height, msg.width)
            depth = millimetres.astype(np.float64) / 1000.0
        else:
            metres = np.asarray(msg.data).view(np.float32).reshape(msg.height, msg.width)
            depth = metres.astype(np.float64)
        top = max(0, round(cy) - self.scan_height // 2)
        rows = depth[top : top + self.scan_height].astype(np.float64)
        u = np.arange(msg.width)
        angles = np.arctan2(cx - u, fx)  # left of centre is positive
        stretch = np.sqrt(1.0 + ((u - cx) / fx) ** 2)
        ranges = rows * stretch
        ranges[~np.isfinite(ranges) | (ranges < self.range_min) | (ranges > self.range_max)] = (
            np.inf
        )
        best = ranges.min(axis=0)[::-1]  # increasing angle
        angle_min, angle_max = float(angles[-1]), float(angles[0])
        self.pub.publish(
            types().cls("sensor_msgs/LaserScan")(
                _header(msg.header.stamp, self.frame),
                angle_min,
                angle_max,
                (angle_max - angle_min) / max(1, msg.width - 1),
                0.0,
                0.0,
                self.range_min,
                self.range_max,
                best.astype(np.float32),
                np.zeros(0, dtype=np.float32),
            )
        )


def _header(stamp: Any, frame: str) -> Any:
    return types().cls("std_msgs/Header")(0, stamp, frame)


def _depth_to_scan(rt: LaunchRuntime, spec: LaunchNode, node: Node) -> None:
    _DepthToScan(node)


NODE_TYPES: dict[tuple[str, str], Starter] = {
    ("robot_state_publisher", "robot_state_publisher"): _robot_state_publisher,
    ("robot_state_publisher", "state_publisher"): _robot_state_publisher,
    ("joint_state_publisher", "joint_state_publisher"): _joint_state_publisher,
    ("joint_state_publisher_gui", "joint_state_publisher_gui"): _joint_state_publisher,
    ("rviz", "rviz"): _rviz,
    ("arbotix_python", "arbotix_driver"): _arbotix,
    ("gazebo_ros", "gzserver"): _gzserver,
    ("gazebo_ros", "debug"): _gzserver,  # empty_world.launch's debug:=true (gzserver in gdb)
    ("gazebo_ros", "gzclient"): _gzclient,
    ("gazebo_ros", "spawn_model"): _spawn_model,
    ("controller_manager", "spawner"): _spawner,
    ("controller_manager", "controller_manager"): _spawner,
    ("tf", "static_transform_publisher"): _static_transform,
    ("tf2_ros", "static_transform_publisher"): _static_transform,
    ("teleop_twist_keyboard", "teleop_twist_keyboard.py"): _teleop,
    ("depthimage_to_laserscan", "depthimage_to_laserscan"): _depth_to_scan,
}
"""What ``belvedere launch`` can start, by (package, type)."""
