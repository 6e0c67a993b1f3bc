"""``PhysicsSimulation``: a world stepped by MuJoCo on the graph's clock, robots spawned
into it with their Gazebo plugins, as ``gzserver`` + gazebo_ros do.

One physics step per ``max_step_size`` of simulated time (1 kHz unless the world says
otherwise), each followed by every plugin's update. A step that leaves NaN or absurd speeds,
or that MuJoCo itself gives up on (its warnings counted in MjData, read after every step: it
resets a state it cannot integrate to the start, mid-run), stops the physics with one error
naming the likely cause (or resets the world, if asked).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Final

import mujoco
import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import GazeboPlugin, Pose, RobotModel, XmlData, transform
from belvedere.errors import SourceLocation
from belvedere.graph import Graph, Node
from belvedere.packages import PackageIndex
from belvedere.sim.physics._builder import RobotBuild, add_robot
from belvedere.sim.physics._cameras import CameraSensor, DepthCamera
from belvedere.sim.physics._diff_drive import DiffDrive
from belvedere.sim.physics._engine import Engine
from belvedere.sim.physics._lighting import add_scene
from belvedere.sim.physics._model_plugins import GroundTruth, JointStates, PlanarMove
from belvedere.sim.physics._plugin import Plugin, PluginContext
from belvedere.sim.physics._robot_namespace import with_robot_namespace
from belvedere.sim.physics._ros_control import RosControl
from belvedere.sim.physics._sensors import ImuSensor, LaserSensor
from belvedere.sim.physics._skid_steer import SkidSteer
from belvedere.sim.physics._spec import ModelError
from belvedere.sim.physics._world_build import add_world
from belvedere.tf import Transform
from belvedere.world import SDFError, WorldModel, WorldModelEntry, empty_world, saved_robot

__all__ = ["PLUGINS", "PhysicsSimulation", "SpawnedRobot"]

logger = logging.getLogger("belvedere.physics")

Matrix4 = npt.NDArray[np.float64]

PluginFactory = Callable[[PluginContext], Plugin]

HEALTH_CHECK_STEPS: Final = 50
"""How often the state is checked for NaN and absurd speeds (MuJoCo's own warnings, which
catch most divergences, are read after every batch of steps)."""

PLUGINS: dict[str, PluginFactory] = {
    "libgazebo_ros_diff_drive.so": DiffDrive,
    "libgazebo_ros_p3d.so": GroundTruth,
    "libgazebo_ros_joint_state_publisher.so": JointStates,
    "libgazebo_ros_planar_move.so": PlanarMove,
    "libgazebo_ros_skid_steer_drive.so": SkidSteer,
    "libgazebo_ros_imu.so": ImuSensor,
    "libgazebo_ros_control.so": RosControl,
}
"""Model plugins (``<gazebo><plugin filename=…>``) by file name."""

SENSOR_PLUGINS: dict[str, PluginFactory] = {
    "libgazebo_ros_laser.so": LaserSensor,
    "libgazebo_ros_gpu_laser.so": LaserSensor,
    "libgazebo_ros_camera.so": CameraSensor,
    "libgazebo_ros_openni_kinect.so": DepthCamera,
    "libgazebo_ros_depth_camera.so": DepthCamera,
    "libgazebo_ros_imu_sensor.so": ImuSensor,
}
"""Sensor plugins (``<sensor><plugin filename=…>``) by file name."""


@dataclass
class SpawnedRobot:
    name: str
    model: RobotModel
    build: RobotBuild
    plugins: list[Plugin] = field(default_factory=list)
    packages: PackageIndex | None = None
    """Where its ``package://`` meshes were found (for a saved world to name the files)."""

    def published_joints(self) -> set[str]:
        """Joints some plugin reports on joint_states."""
        return {j for p in self.plugins for j in p.joint_names()}


def _saved_robots(world: WorldModel) -> list[tuple[WorldModelEntry, RobotModel, Pose]]:
    """The world's models that are robots (saved with their plugins and sensors), each as
    the robot to spawn where it stands; one that cannot be a robot stays a model of the
    world (rigid), with a warning."""
    out = []
    for entry in world.models:
        if not entry.robot:
            continue
        try:
            robot, pose = saved_robot(entry)
        except SDFError as err:
            logger.warning(
                "%s: warning: model %r has plugins and sensors but cannot run as a robot (%s):"
                " it is one rigid body, without them",
                err.location or entry.source,
                entry.name,
                err.message,
            )
            continue
        out.append((entry, robot, pose))
    return out


class PhysicsSimulation:
    """A world (default: the empty world, a ground plane and the sun) and the robots in it,
    stepped on ``graph``'s executor."""

    def __init__(
        self,
        graph: Graph,
        world: WorldModel | None = None,
        *,
        auto_reset: bool = False,
        node: Node | None = None,
    ) -> None:
        """``node``: the simulation's node (default: a new one named ``gazebo``)."""
        self.graph = graph
        world = world or empty_world()
        saved = _saved_robots(world)
        self.saved: dict[str, WorldModelEntry] = {entry.name: entry for entry, _, _ in saved}
        """The robots the world file holds (a world saved with them), as it wrote them."""
        self.world = replace(
            world, models=tuple(m for m in world.models if m.name not in self.saved)
        )
        self.engine = Engine(self.world.physics)
        self.world_roots: dict[str, str] = {}
        self._build_world()  # first: a world MuJoCo refuses leaves nothing on the graph
        self.robots: dict[str, SpawnedRobot] = {}
        self._stepping: list[Plugin] | None = None
        """The plugins of every robot, in order (None: to be listed again, robots changed)."""
        self.auto_reset = auto_reset
        self.node = node or graph.create_node("gazebo")
        self.stopped_reason: str | None = None
        self.steps = 0
        self.warned: set[int] = set()
        """MuJoCo's warnings already logged (each once per run)."""
        self.after_step: list[Callable[[], None]] = []
        self.every_step: list[Callable[[], bool]] = []
        """Whether an ``after_step`` hook wants to run after every step now (no batching)."""
        self.engine.on_recompile.append(self._bind_all)
        self.timer = self.node.timer(self.engine.physics.max_step_size, self.physics_step)
        for entry, robot, pose in saved:
            self.spawn(robot, name=entry.name, pose=pose)

    def world_entry(self, name: str) -> WorldModelEntry | None:
        """The model of that name the world file holds (a robot saved in it too), if any."""
        return self.world.model(name) or self.saved.get(name)

    def _build_world(self) -> None:
        try:
            self.world_roots = add_world(self.engine.spec, self.world)
            add_scene(self.engine.spec, self.world)
            self.engine.compile()
        except ValueError as err:  # what the builder's checks do not catch first
            msg = f"MuJoCo refused the world: {err}"
            raise ModelError(msg, SourceLocation(self.world.path or "<world>")) from None

    @property
    def plugins(self) -> list[Plugin]:
        return [p for r in self.robots.values() for p in r.plugins]

    def _each_step(self) -> list[Plugin]:
        """:attr:`plugins`, listed once per change of robots rather than twice a step."""
        stepping = self._stepping
        if stepping is None:
            stepping = self._stepping = self.plugins
        return stepping

    # --- robots --------------------------------------------------------------------------------
    def spawn(
        self,
        model: RobotModel,
        *,
        name: str | None = None,
        pose: Pose = Pose(),
        packages: PackageIndex | None = None,
        robot_namespace: str = "",
    ) -> SpawnedRobot:
        """Add a robot with its plugins (spawn_model). Its ``<gazebo>`` plugins and sensors
        start now; an unknown plugin is one warning and the rest runs. ``robot_namespace``:
        the namespace of its plugins that name none (spawn_model's ``-robot_namespace``)."""
        name = name or model.name
        model = with_robot_namespace(model, robot_namespace)
        if name in self.robots or name in self.world_roots:
            msg = f"a model named {name!r} already exists in the simulation"
            raise ModelError(msg)
        spec = self.engine.spec
        build = add_robot(
            spec, model, name=name, pose=pose, packages=packages, scene=self.world.scene
        )
        robot = SpawnedRobot(name, model, build, packages=packages)
        try:
            robot.plugins = self._make_plugins(robot)
            for plugin in robot.plugins:
                try:
                    plugin.prepare(spec)
                except ValueError as err:  # MjSpec refuses a name or a value
                    msg = f"plugin {plugin.ctx.name!r}: MuJoCo refused it: {err}"
                    raise ModelError(msg, plugin.ctx.source) from None
            self.robots[name] = robot
            self._stepping = None
            try:
                self.engine.compile()
            except ValueError as err:
                msg = f"MuJoCo refused robot {name!r}: {err}"
                raise ModelError(msg, model.link(model.root_link.name).source.best) from None
        except BaseException:
            # Nothing of a robot that failed to spawn stays in the world.
            self.robots.pop(name, None)
            self._stepping = None
            for plugin in robot.plugins:
                plugin.active = False
            self._remove_from_spec(name)
            raise
        return robot

    def _make_plugins(self, robot: SpawnedRobot) -> list[Plugin]:
        plugins: list[Plugin] = []
        for ext in robot.model.gazebo:
            for plugin in ext.plugins:
                made = self._plugin(PLUGINS, robot, plugin, reference=ext.reference)
                if made is not None:
                    plugins.append(made)
            for sensor in ext.sensors:
                plugins += self._sensor_plugins(robot, sensor, ext.reference)
        return plugins

    def _plugin(
        self,
        registry: dict[str, PluginFactory],
        robot: SpawnedRobot,
        plugin: GazeboPlugin,
        *,
        reference: str | None,
        sensor: XmlData | None = None,
    ) -> Plugin | None:
        filename = plugin.filename.strip()
        factory = registry.get(filename)
        if factory is None:
            logger.warning(
                "%s: warning: plugin %r (%s): unknown plugin; the simulation runs without it",
                plugin.source.best or robot.model.path,
                plugin.name,
                filename,
            )
            return None
        ctx = PluginContext.of(
            self.engine,
            self.graph,
            robot.build,
            plugin,
            reference=reference,
            sensor=sensor,
        )
        return factory(ctx)

    def _sensor_plugins(
        self, robot: SpawnedRobot, sensor: XmlData, reference: str | None
    ) -> list[Plugin]:
        out: list[Plugin] = []
        for child in sensor.children:
            if child.tag != "plugin":
                continue
            plugin = GazeboPlugin(
                name=child.attr("name") or "",
                filename=child.attr("filename") or "",
                params=child.children,
                source=child.source,
            )
            made = self._plugin(SENSOR_PLUGINS, robot, plugin, reference=reference, sensor=sensor)
            if made is not None:
                out.append(made)
        return out

    def _bind_all(self) -> None:
        for plugin in self.plugins:
            plugin.bind()

    # --- stepping ------------------------------------------------------------------------------
    def physics_step(self) -> None:
        """MuJoCo steps, then the update of every plugin due (the graph's timer calls this).

        Steps run in one batch up to the next step at which a plugin acts, or anything else
        on the graph is due: plugins see every step at which they would have acted, at the
        same simulated time, and nothing else notices the batch. A plugin whose next update
        (:meth:`Plugin.next_update_ns`) lies beyond the batch is not called. Plugins that
        want every step (a motor at its torque limit) are updated after each step of the
        batch, until one has something to deliver."""
        if self.stopped_reason is not None:
            return
        steps, due, each = self._batch()
        if each and due is not None:
            self._step_each(steps, due, each)
            return
        engine = self.engine
        mujoco.mj_step(engine.m, engine.d, steps)
        if steps > 1:
            executor = self.graph.executor
            executor.advance_to(executor.now_ns() + (steps - 1) * self.timer.period_ns)
        if self._stepped(steps):
            now = self.graph.now_ns()
            for plugin in self._each_step() if due is None else due:
                if plugin.active:
                    plugin.update(now)
            for hook in self.after_step:
                hook()

    def _step_each(self, steps: int, due: list[Plugin], each: list[Plugin]) -> None:
        """``steps`` steps one by one, ``each`` updated after every one and ``due`` after the
        last (in the plugins' order); cut short when an update leaves a message to deliver,
        so that it is delivered at the step it was sent, as between batches."""
        m, d = self.engine.m, self.engine.d
        executor = self.graph.executor
        period = self.timer.period_ns
        last = [p for p in self._each_step() if p in due or p in each]
        now = executor.now_ns()
        for i in range(steps):
            mujoco.mj_step(m, d)
            if i:
                now += period
                executor.advance_to(now)
            if not self._stepped(1):
                return
            for plugin in last if i == steps - 1 else each:
                if plugin.active:
                    plugin.update(now)
            for hook in self.after_step:
                hook()
            if executor.has_ready():
                return

    def _stepped(self, steps: int) -> bool:
        """Count ``steps`` just taken and look at their health: False when the physics
        diverged (stopped, or the world reset)."""
        engine = self.engine
        before = self.steps
        self.steps += steps
        for warning in engine.take_warnings():
            if warning.broken:
                self._diverged(warning.text)
                return False
            if warning.kind not in self.warned:
                self.warned.add(warning.kind)
                logger.warning("physics at t=%.3f s: %s", self.graph.now_ns() / 1e9, warning.text)
        if self.steps // HEALTH_CHECK_STEPS != before // HEALTH_CHECK_STEPS:
            problem = engine.healthy()
            if problem is not None:
                self._diverged(problem)
                return False
        return True

    def _batch(self) -> tuple[int, list[Plugin] | None, list[Plugin]]:
        """How many steps to take now — through the first step at which a plugin acts, no
        further than the executor's horizon; one while a hook wants every step — the plugins
        due at its last step (None: all of them), and those that want every step."""
        for wants in self.every_step:
            if wants():
                return 1, None, []
        executor = self.graph.executor
        now = executor.now_ns()
        step = self.timer.period_ns
        last = executor.horizon_ns()
        dues: list[tuple[int, Plugin]] = []
        each: list[Plugin] = []
        for plugin in self._each_step():
            if not plugin.active:
                continue
            due = plugin.next_update_ns(now)
            if due is None:
                each.append(plugin)
                continue
            dues.append((due, plugin))
            if due <= now:
                last = now
            elif due < last:
                last = min(last, now + -(-(due - now) // step) * step)
        steps = 1 + max(0, (last - now) // step)
        end = now + (steps - 1) * step
        return steps, [plugin for due, plugin in dues if due <= end], each

    def _diverged(self, problem: str) -> None:
        cause = self._likely_cause()
        if self.auto_reset:
            logger.error("physics diverged (%s; %s): resetting the world", problem, cause)
            self.reset_world()
            return
        self.stopped_reason = f"{problem}; {cause}"
        logger.error(
            "physics diverged at t=%.3f s: %s. Likely cause: %s. The physics is stopped "
            "(the graph keeps running); fix the model, or run with auto-reset",
            self.graph.now_ns() / 1e9,
            problem,
            cause,
        )

    def _likely_cause(self) -> str:
        """The robot link with the lightest or least balanced inertia, where it was written."""
        worst: tuple[float, str] | None = None
        for robot in self.robots.values():
            for link in robot.model.links:
                inertial = link.inertial
                if inertial is None:
                    continue
                smallest = min(inertial.ixx, inertial.iyy, inertial.izz)
                ratio = smallest / max(inertial.mass, 1e-12)
                where = link.source.best
                text = f"the inertia of link {link.name!r} ({where})"
                if worst is None or ratio < worst[0]:
                    worst = (ratio, text)
        return worst[1] if worst else "a world model's mass or inertia"

    def reset_world(self) -> None:
        """Every model back to its start pose, still (Gazebo's reset_world)."""
        self.engine.reset()
        self.stopped_reason = None
        for plugin in self.plugins:
            plugin.reset()

    @property
    def odom_frame(self) -> str | None:
        """The odometry frame of the first diff-drive base (the viewer's fixed frame)."""
        for plugin in self.plugins:
            frame = getattr(plugin, "odom_frame", None)
            if isinstance(frame, str):
                return frame
        return None

    def sensor_topics(self) -> list[tuple[str, str]]:
        """(rviz display kind, topic) for each sensor's main output, to show them at once."""
        out: list[tuple[str, str]] = []
        for plugin in self.plugins:
            if isinstance(plugin, LaserSensor):
                out.append(("LaserScan", plugin.pub.name))
            elif isinstance(plugin, DepthCamera):
                out.append(("PointCloud2", plugin.points_pub.name))
            elif isinstance(plugin, CameraSensor):
                out.append(("Image", plugin.image_pub.name))
        return out

    # --- state ---------------------------------------------------------------------------------
    def model_pose(self, name: str) -> Matrix4:
        """A model's world pose: a robot's root link, a world model's frame."""
        engine = self.engine
        robot = self.robots.get(name)
        if robot is not None:
            return engine.link_pose(robot.build, robot.model.root_link.name)
        entry = self.world.model(name)
        root = self.world_roots.get(name)
        if entry is None or root is None:
            known = ", ".join(sorted([*self.robots, *self.world_roots]))
            msg = f"no model named {name!r} (models: {known})"
            raise KeyError(msg)
        if root == "world" or not entry.links:
            return transform(entry.pose)
        body_pose = engine.body_pose(engine.body_id(root))
        result: Matrix4 = body_pose @ np.linalg.inv(transform(entry.links[0].pose))
        return result

    def model_poses(self) -> dict[str, Transform]:
        """World poses of the world's movable models (for the viewer)."""
        return {
            name: Transform.from_matrix(self.model_pose(name))
            for name, root in self.world_roots.items()
            if root != "world"
        }

    def model_names(self) -> list[str]:
        return [*self.world_roots, *self.robots]

    def model_twist(self, name: str) -> npt.NDArray[np.float64]:
        """(angular, linear) world velocity of a model's root body."""
        robot = self.robots.get(name)
        if robot is not None:
            body = robot.build.root_body
        else:
            body = self.world_roots.get(name, "")
            if not body:
                self.model_pose(name)  # raises the KeyError naming the models
        if body == "world":
            return np.zeros(6)
        return self.engine.body_velocity(self.engine.body_id(body))

    def set_model_pose(self, name: str, pose: Pose) -> None:
        """Teleport a free model (set_model_state); its velocity is zeroed."""
        robot = self.robots.get(name)
        if robot is not None and robot.build.free_joint is not None:
            root_offset = robot.build.link_body[robot.model.root_link.name][1]
            target = transform(pose) @ np.linalg.inv(root_offset)
            self.engine.set_free_pose(robot.build.free_joint, target)
            return
        entry = self.world.model(name)
        if entry is not None and self.world_roots.get(name, "world") != "world":
            self.engine.set_free_pose(
                f"{name}/free", transform(pose) @ transform(entry.links[0].pose)
            )
            return
        self.model_pose(name)  # unknown: raises
        msg = f"model {name!r} is static or fixed to the world; it cannot be moved"
        raise KeyError(msg)

    def add_model(
        self, entry: WorldModelEntry, *, name: str, pose: Pose, origin: str | None = None
    ) -> None:
        """Add an SDF model to the world (spawn_sdf_model). ``origin``: the ``model://NAME``
        it came from, if it came from the model path (a saved world includes it from
        there); by default the entry's own ``uri``. A model with plugins or sensors is a
        robot, spawned as one (its plugins and sensors run)."""
        name = name or entry.name
        if name in self.robots or name in self.world_roots:
            msg = f"a model named {name!r} already exists in the simulation"
            raise ModelError(msg)
        placed = replace(entry, name=name, pose=pose, uri=origin or entry.uri)
        robots = _saved_robots(WorldModel(models=(placed,)))
        if robots:
            _, robot, at = robots[0]
            self.spawn(robot, name=name, pose=at)
            return
        try:
            roots = add_world(
                self.engine.spec, WorldModel(models=(placed,)), scene=self.world.scene
            )
            self.engine.compile()
        except (ModelError, ValueError) as err:
            self._remove_from_spec(name)  # the world stays as it was
            if isinstance(err, ModelError):
                raise
            msg = f"MuJoCo refused model {name!r}: {err}"
            raise ModelError(msg, entry.source) from None
        self.world_roots.update(roots)
        self.world = replace(self.world, models=(*self.world.models, placed))

    def delete(self, name: str) -> None:
        """Remove a robot or a world model (delete_model)."""
        robot = self.robots.pop(name, None)
        self._stepping = None
        if robot is None and name not in self.world_roots:
            self.model_pose(name)  # raises the KeyError naming the models
        for plugin in robot.plugins if robot else []:
            plugin.active = False
        self._remove_from_spec(name)
        self.world_roots.pop(name, None)
        self.world = replace(
            self.world, models=tuple(m for m in self.world.models if m.name != name)
        )
        self.engine.compile()

    def _remove_from_spec(self, name: str) -> None:
        spec = self.engine.spec
        prefix = f"{name}/"
        for actuator in list(spec.actuators):
            if actuator.name.startswith(prefix):
                spec.delete(actuator)
        for exclude in list(spec.excludes):
            if exclude.bodyname1.startswith(prefix):
                spec.delete(exclude)
        for body in list(spec.worldbody.bodies):
            if body.name.startswith(prefix):
                spec.delete(body)
        for geom in list(spec.worldbody.geoms):
            if geom.name.startswith(prefix):
                spec.delete(geom)
        for material in list(spec.materials):
            if material.name.startswith(prefix):
                spec.delete(material)

    @property
    def paused(self) -> bool:
        return self.graph.executor.paused

    @paused.setter
    def paused(self, value: bool) -> None:
        self.graph.executor.pause(value)

    # --- the viewer's controls -----------------------------------------------------------------
    def pause(self, paused: bool) -> None:
        self.graph.executor.pause(paused)

    def step(self) -> None:
        """While paused: one physics step (the viewer's Step button)."""
        self.graph.executor.step(self.engine.physics.max_step_size)

    def reset(self) -> None:
        self.graph.executor.post(self.reset_world)

    def set_rtf(self, rtf: float | None) -> None:
        self.graph.executor.set_rtf(rtf)
