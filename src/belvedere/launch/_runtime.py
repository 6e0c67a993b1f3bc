"""Running a :class:`LaunchConfig` on one graph: the parameters set, every node started.

Nodes are found in :mod:`belvedere.nodes` by ROS package and type and run in this process; a Python
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
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from belvedere import nodes
from belvedere.description.urdf import RobotModel
from belvedere.errors import BelvedereError, SourceLocation
from belvedere.fileio import FileWriteError, write_file
from belvedere.graph import Graph, Node, ZenohTransport
from belvedere.launch._compiled import find_compiled, is_compiled, unbuilt_hint
from belvedere.launch._lifecycle import LaunchProcess, ProcessMonitor
from belvedere.launch._listing import process_name
from belvedere.launch._model import LaunchConfig, LaunchError, LaunchNode
from belvedere.launch._names import canonical
from belvedere.packages import BUILTIN_PACKAGES, PackageIndex
from belvedere.pyscripts import ScriptError, script_command
from belvedere.tf import JointStatePublisher

__all__ = ["LaunchRuntime", "find_script"]

logger = logging.getLogger("belvedere.launch")


def find_script(root: Path, executable: str, package: str | None = None) -> Path | None:
    """Where rosrun (and roslaunch) finds a package's ``executable``: ``scripts/``,
    ``nodes/``, the package's top, anywhere below it, then what catkin built of it (see
    :mod:`belvedere.launch._compiled`; ``package``: its name, if not its directory's). In the
    packages belvedere provides only ``scripts/`` (rospy scripts of ROS's own, as dynparam;
    the rest are belvedere's own nodes)."""
    if root.is_relative_to(BUILTIN_PACKAGES):
        found = root / "scripts" / executable
        return found if found.is_file() else None
    for candidate in (
        root / "scripts" / executable,
        root / "nodes" / executable,
        root / executable,
    ):
        if candidate.is_file():
            return candidate
    below = next((p for p in sorted(root.rglob(executable)) if p.is_file()), None)
    return below or find_compiled(root, package or root.name, executable)


def _which_wins(a: LaunchNode, b: LaunchNode) -> str:
    static = [n for n in (a, b) if n.type == "static_transform_publisher"]
    if len(static) == 1:
        other = b if static[0] is a else a
        return (
            f"tf keeps whichever came last, so {other.full_name}'s updates win over the "
            f"static one — remove {static[0].full_name}: {other.full_name} publishes it itself"
        )
    return "tf keeps whichever came last, so the transform jumps between them — keep one"


@dataclass
class LaunchRuntime:
    """The running launch: its graph, simulation, viewer and subprocesses."""

    config: LaunchConfig
    graph: Graph
    packages: PackageIndex
    headless: bool = False
    viewer_options: dict[str, Any] = field(default_factory=dict)
    sim: Any = None
    sim_controls: Any = None
    viewer: Any = None
    joint_publisher: JointStatePublisher | None = None
    gui_joints: bool = False
    rviz_config: str | None = None
    want_viewer: bool = False
    canvases: list[Any] = field(default_factory=list)
    """2D simulations the viewer draws (turtlesim's window)."""
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
    script_argv: dict[int, list[str]] = field(default_factory=dict)
    """Each script process's arguments (a respawn gets the same)."""
    in_process: list[tuple[LaunchNode, Node]] = field(default_factory=list)
    """The nodes running in this process, with their specs."""
    finished: dict[str, int] = field(default_factory=dict)
    """In-process nodes that ended by themselves: full name → exit status."""
    closers: list[Callable[[], None]] = field(default_factory=list)
    """Run by :meth:`close`, last added first (a recorder closes its bag)."""
    announce: bool = False
    """Say each process started, as roslaunch does (rosrun does not)."""
    started: int = 0
    """Processes started so far (roslaunch numbers them: ``process[name-N]``)."""
    lifecycle: bool = False
    """Nodes live and die as roslaunch's processes (:mod:`belvedere.launch._lifecycle`): one
    that fails dies alone, with roslaunch's line, rather than failing the launch."""
    joined: bool = False
    """The launch joined a running graph (as roslaunch uses a running master)."""
    monitor: ProcessMonitor | None = None
    ros1_master: Any = None
    """belvedere's ROS 1 master, once a compiled node needs one."""
    screen_stdout: int | None = None
    """Where scripts with ``output="screen"`` print their standard output: this process's
    (None), or another file descriptor (``--echo`` keeps stdout to itself: 2, stderr)."""

    def param_source(self, name: str) -> SourceLocation | None:
        param = self.config.params.get(canonical(name))
        return None if param is None else param.source

    def start(self) -> None:
        self._begin_lifecycle()
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
        self._warn_transform_conflicts()
        for spec in self.config.nodes:
            self._start(spec)
        for action in [*self.deferred, *self.controllers]:
            self._call(action)
        if self.missing:
            logger.warning(
                "not started (belvedere has no such node yet): %s; the rest of the launch runs",
                ", ".join(self.missing),
            )
        if self.want_viewer and not self.headless:
            self._open_viewer()

    def start_test(self, spec: LaunchNode) -> LaunchProcess | None:
        """Start a ``<test>`` node once the rest is up (rostest's way), as a process of the
        launch (:attr:`lifecycle`); its process, or None if it could not start."""
        assert self.monitor is not None, "tests run with roslaunch's lifecycle"
        before = len(self.monitor.procs)
        deferred, controllers = len(self.deferred), len(self.controllers)
        self._start(spec)
        for action in [*self.deferred[deferred:], *self.controllers[controllers:]]:
            action()
        return self.monitor.procs[before] if len(self.monitor.procs) > before else None

    def _warn_transform_conflicts(self) -> None:
        """Two nodes that will publish the same frame's transform: say so once, with both
        launch lines (tf keeps whichever came last, so a localizer's updates win over a
        static one, and the frame jumps between them whenever the static one is resent)."""
        params = self.graph.params
        claimed: dict[str, tuple[str, LaunchNode]] = {}
        for spec in self.config.nodes:

            def param(name: str, default: Any, spec: LaunchNode = spec) -> Any:
                return params.get(f"{spec.full_name}/{name}", default)

            for parent, child in nodes.transforms(spec, param):
                first = claimed.setdefault(child, (parent, spec))
                if first[1] is spec:
                    continue
                logger.warning(
                    "warning: two nodes publish the transform %s -> %s: %s (%s) and %s (%s); %s",
                    first[0],
                    child,
                    first[1].full_name,
                    first[1].source,
                    spec.full_name,
                    spec.source,
                    _which_wins(first[1], spec),
                )

    def _start(self, spec: LaunchNode) -> None:
        starter = nodes.find(spec.pkg, spec.type)
        if starter is None:
            script = self._user_script(spec)
            if script is not None:
                if self.run_script(spec, script):
                    self._started(spec, f"with pid [{self.processes[-1][1].pid}]")
                return
            unbuilt = self._unbuilt(spec)
            self.missing.append(
                f"{spec.pkg}/{spec.type} ({spec.full_name}, {spec.source}"
                + (f": {unbuilt})" if unbuilt else ")")
            )
            if self.lifecycle:
                self.started += 1  # roslaunch numbers a node it cannot find too
            return
        node = self.graph.create_node(
            spec.name, namespace=spec.namespace, remappings=dict(spec.remappings)
        )
        self.in_process.append((spec, node))
        if self.lifecycle:
            self._started(spec, "in this process")
            self._start_in_process(spec, node, process_name(spec, self.started))
            return
        self._call(lambda: starter(self, spec, node))
        self._started(spec, "in this process")

    @staticmethod
    def _call(action: Callable[[], None]) -> None:
        """A node's start (or deferred start): its error is the launch's, at its line."""
        try:
            action()
        except nodes.StartError as err:
            raise LaunchError(err.message, err.location, hint=err.hint, trail=err.trail) from None

    # --- user scripts ------------------------------------------------------------------------
    def _user_script(self, spec: LaunchNode) -> Path | None:
        try:
            root = self.packages.find(spec.pkg, requested_at=spec.source)
        except BelvedereError:
            return None
        return find_script(root, spec.type, spec.pkg)

    def _unbuilt(self, spec: LaunchNode) -> str | None:
        try:
            root = self.packages.find(spec.pkg, requested_at=spec.source)
        except BelvedereError:
            return None
        return unbuilt_hint(root, spec.type)

    def _ros1_env(self) -> dict[str, str]:
        """What a compiled (roscpp) node needs: belvedere's ROS 1 master for this graph,
        started the first time one is asked for, as roslaunch starts a roscore."""
        if self.ros1_master is None:
            from belvedere.ros1wire import start_master

            self.ros1_master = start_master(self.graph, port=0)
            logger.info("ROS 1 master for compiled nodes: %s", self.ros1_master.uri)
        env = {"ROS_MASTER_URI": self.ros1_master.uri}
        if "ROS_IP" not in os.environ and "ROS_HOSTNAME" not in os.environ:
            env["ROS_HOSTNAME"] = "127.0.0.1"  # the master serves loopback only
        return env

    def _graph_env(self) -> dict[str, str]:
        """What a script node needs: this launch's graph (domain, endpoint) and package path."""
        env = {"ROS_PACKAGE_PATH": os.pathsep.join(str(p) for p in self.packages.search_path)}
        transport = self.graph.transport
        if isinstance(transport, ZenohTransport):
            env["BELVEDERE_DOMAIN"] = str(transport.domain)
            env["BELVEDERE_ENDPOINT"] = transport.endpoint
        return env

    def run_script(self, spec: LaunchNode, script: Path, *, argv: list[str] | None = None) -> bool:
        """Run a user's script as the node ``spec`` (its name, namespace and remaps as
        arguments, as roslaunch passes them, or ``argv`` as given, as rosrun passes them; the
        graph's domain and endpoint in its environment); False, with one message, if it
        cannot run."""
        extra: dict[str, str] = {}
        if is_compiled(script):
            command = [str(script)]
            extra = self._ros1_env()
        else:
            try:
                command = script_command(script)
            except ScriptError as err:
                logger.error(
                    "%s: %s (node %s not started)", err.location, err.message, spec.full_name
                )
                return False
        env = {**os.environ, **self._graph_env(), **extra, **dict(spec.env)}
        if argv is None:
            argv = [*shlex.split(spec.args), f"__name:={spec.name}"]
            if spec.namespace != "/":
                argv.append(f"__ns:={spec.namespace}")
            argv += [f"{a}:={b}" for a, b in spec.remappings]
        if self.lifecycle:
            return self._run_script_process(spec, script, command, argv, env)
        output = None if spec.output == "screen" else subprocess.DEVNULL
        process = subprocess.Popen(
            [*command, *argv],
            env=env,
            cwd=spec.cwd,
            stdout=self.screen_stdout if output is None else output,
            stderr=output,
        )
        self.processes.append((spec, process))
        self.script_argv[id(process)] = argv
        return True

    # --- roslaunch's process lifecycle (see belvedere.launch._lifecycle) ------------------------
    def _begin_lifecycle(self) -> None:
        if not self.lifecycle:
            return
        self.monitor = ProcessMonitor(joined=self.joined)
        if not self.joined:
            self.started = 1  # roslaunch's own roscore: its rosout is process 1

    def _start_in_process(self, spec: LaunchNode, node: Node, name: str) -> None:
        """A node of this process, as a process of the launch: its start raising is its
        death (exit code 1), not the launch's failure; so is an action it left for later
        (spawn_model's spawn) raising, or one of its timers."""
        assert self.monitor is not None
        try:
            words = shlex.split(spec.args)
        except ValueError:
            words = [spec.args]
        cmd = [f"{spec.pkg}/{spec.type}", *words, *(f"{a}:={b}" for a, b in spec.remappings)]
        cmd += [f"__name:={spec.name}", f"__log:={self.monitor.log_file(name)}"]
        process = LaunchProcess(
            spec, name, cmd, os.getpid(), node=node, finished=lambda: self.finished.get(full)
        )
        full = node.full_name
        process.start = lambda: self._restart_in_process(process)
        self.monitor.add(process)
        self._run_in_process(process)

    def _crash(self, process: LaunchProcess) -> Callable[[Exception], None]:
        def crashed(err: Exception) -> None:
            assert self.monitor is not None
            self.monitor.failed(process, err)

        return crashed

    def _run_in_process(self, process: LaunchProcess) -> None:
        assert self.monitor is not None
        assert process.node is not None
        spec = process.spec
        starter = nodes.find(spec.pkg, spec.type)
        assert starter is not None
        process.node.on_crash = self._crash(process)  # its run raising is its death too
        deferred, controllers = len(self.deferred), len(self.controllers)
        try:
            starter(self, spec, process.node)
        except Exception as err:  # noqa: BLE001 (a node's crash is its process's death)
            del self.deferred[deferred:], self.controllers[controllers:]
            self.monitor.failed(process, err)
            return
        for actions, first in ((self.deferred, deferred), (self.controllers, controllers)):
            actions[first:] = [self._guarded(process, a) for a in actions[first:]]

    def _guarded(self, process: LaunchProcess, action: Callable[[], None]) -> Callable[[], None]:
        def run() -> None:
            assert self.monitor is not None
            if process.exit_code is not None:
                return  # the node died before its turn came
            try:
                action()
            except Exception as err:  # noqa: BLE001 (a node's crash is its process's death)
                self.monitor.failed(process, err)

        return run

    def _restart_in_process(self, process: LaunchProcess) -> None:
        """respawn: a new node of the same name, started as the first was; what it leaves
        for later runs now (everything else exists by now)."""
        spec, old = process.spec, process.node
        if old is not None and not old.closed:
            old.shutdown()
        self.finished.pop(spec.full_name, None)
        node = self.graph.create_node(
            spec.name, namespace=spec.namespace, remappings=dict(spec.remappings)
        )
        self.in_process = [(s, n) for s, n in self.in_process if n is not old] + [(spec, node)]
        process.node = node
        if self.announce:
            logger.info("process[%s]: started in this process", process.name)
        deferred, controllers = len(self.deferred), len(self.controllers)
        self._run_in_process(process)
        later = [*self.deferred[deferred:], *self.controllers[controllers:]]
        del self.deferred[deferred:], self.controllers[controllers:]
        for action in later:
            action()

    def _run_script_process(
        self,
        spec: LaunchNode,
        script: Path,
        command: list[str],
        argv: list[str],
        env: dict[str, str],
    ) -> bool:
        """A script as roslaunch runs it: ``__log:=`` its log file, stdout to that log
        unless ``output="screen"``, stderr on the terminal."""
        assert self.monitor is not None
        name = process_name(spec, self.started + 1)  # the number _started gives it
        argv = [*argv, f"__log:={self.monitor.log_file(name)}"]
        process = LaunchProcess(spec, name, [str(script), *argv], 0)
        process.start = lambda: self._popen_script(process, [*command, *argv], env)
        self._popen_script(process, [*command, *argv], env, first=True)
        self.monitor.add(process)
        return True

    def _popen_script(
        self, process: LaunchProcess, words: list[str], env: dict[str, str], *, first: bool = False
    ) -> None:
        assert self.monitor is not None
        spec = process.spec
        log = None
        if spec.output != "screen":
            log = self.monitor.stdout_for(process.name, append=spec.respawn and not first)
        stdout: Any = self.screen_stdout if spec.output == "screen" else (log or subprocess.DEVNULL)
        try:
            popen = subprocess.Popen(words, env=env, cwd=spec.cwd, stdout=stdout)
        finally:
            if log is not None:
                log.close()
        process.popen, process.pid = popen, popen.pid
        self.processes.append((spec, popen))
        if self.announce and not first:
            logger.info("process[%s]: started with pid [%d]", process.name, popen.pid)

    def _started(self, spec: LaunchNode, how: str) -> None:
        """roslaunch's line for each process it starts (an in-process node counts as one)."""
        self.started += 1
        if self.announce:
            logger.info("process[%s]: started %s", process_name(spec, self.started), how)

    def ended_in_process(self) -> LaunchNode | None:
        """A required in-process node that has ended (the launch then ends), if any."""
        if self.monitor is not None:
            return None  # poll_processes looks at every process
        for spec, node in self.in_process:
            if node.closed and spec.required:
                return spec
        return None

    def exit_status(self, spec: LaunchNode) -> int:
        """The exit status of a node that has ended (0 if it is unknown): an in-process
        node's own, a script's (128 + N for a script killed by signal N)."""
        status = self.finished.get(spec.full_name)
        if status is not None:
            return status
        for other, process in self.processes:
            if other is spec and process.returncode is not None:
                code = process.returncode
                return 128 - code if code < 0 else code
        return 0

    def poll_processes(self) -> LaunchNode | None:
        """A required node that has exited (the launch then ends), if any; nodes with
        ``respawn`` that exited are started again after their ``respawn_delay``. With
        :attr:`lifecycle`: every process, as roslaunch's monitor looks at them (the node
        whose end ends the launch, if one did)."""
        if self.monitor is not None:
            ended = self.monitor.poll()
            return None if ended is None else ended.spec
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
                        self.run_script(spec, script, argv=self.script_argv.get(id(process)))
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
            rviz_path=self.rviz_config,
            joint_publisher=self.joint_publisher if self.gui_joints else None,
            sim=sim if sim is not None else self.sim_controls,
            packages=self.packages,
            world=getattr(sim, "world", None),
            world_poses=sim.model_poses if sim is not None else None,
            fixed_frame=None if self.rviz_config else getattr(sim, "odom_frame", None),
            canvases=self.canvases,
            **self.viewer_options,
        )
        if sim is not None and not self.rviz_config:
            for kind, topic in sim.sensor_topics():
                self.viewer.add_display(kind, topic)
        sys.stderr.write(f"viewer: {self.viewer.url}\n")

    def close(self) -> None:
        try:
            while self.closers:
                self.closers.pop()()
        finally:
            self._close_rest()

    def _close_rest(self) -> None:
        if self.viewer is not None:
            self.viewer.close()
        if self.monitor is not None:
            self.monitor.stopping()
        for _, process in self.processes:
            if process.poll() is None:
                process.terminate()
                try:
                    process.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    process.kill()
        if self.monitor is not None:
            self.monitor.stopped()
        if self.ros1_master is not None:
            self.ros1_master.close()  # after the nodes that talk to it
