"""``libgazebo_ros_control.so`` and the controller_manager, as gazebo_ros_control's
DefaultRobotHWSim and ros_controllers behave.

Transmissions give each joint one command interface (effort, velocity or position). Without
PID gains (``<ns>/gazebo_ros_control/pid_gains/<joint>``) a velocity joint is driven like
Gazebo's joint motor and a position joint like a stiff servo, both within the URDF effort
limit; with gains, a PID computes the effort. Controllers are loaded from the parameter tree
(``<ns>/<controller>/type``) by the ``load_controller``/``switch_controller`` services — what
``controller_manager spawner`` calls — and run every ``controlPeriod``.
"""

from __future__ import annotations

import itertools
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import mujoco

from belvedere.graph import NS, ActionServer, GoalHandle, Node
from belvedere.msgs import build, message_from_data
from belvedere.sim._commands import CommandGate
from belvedere.sim.physics._builder import ModelError
from belvedere.sim.physics._engine import JointRef
from belvedere.sim.physics._motor import VelocityMotor
from belvedere.sim.physics._plugin import Plugin, PluginContext, RateGate
from belvedere.tf import TransformBroadcaster

__all__ = ["CONTROLLER_TYPES", "RosControl", "spawner"]

logger = logging.getLogger("belvedere.ros_control")

INTERFACES = {"EffortJointInterface": "effort", "VelocityJointInterface": "velocity"}
INTERFACES |= {"PositionJointInterface": "position"}


@dataclass
class Pid:
    """control_toolbox's PID: p, i, d, i_clamp (±), d on the error."""

    p: float
    i: float = 0.0
    d: float = 0.0
    i_clamp: float = 0.0
    integral: float = 0.0
    last_error: float | None = None

    @classmethod
    def from_params(cls, params: Any) -> Pid | None:
        if not isinstance(params, dict) or "p" not in params:
            return None
        clamp = max(
            abs(float(params.get("i_clamp", 0.0))), abs(float(params.get("i_clamp_max", 0.0)))
        )
        return cls(
            float(params["p"]), float(params.get("i", 0.0)), float(params.get("d", 0.0)), clamp
        )

    def __call__(self, error: float, dt: float) -> float:
        if dt <= 0:
            return 0.0
        self.integral += error * dt
        if self.i_clamp > 0 and self.i != 0:
            limit = self.i_clamp / abs(self.i)
            self.integral = max(-limit, min(limit, self.integral))
        derivative = 0.0 if self.last_error is None else (error - self.last_error) / dt
        self.last_error = error
        return self.p * error + self.i * self.integral + self.d * derivative

    def reset(self) -> None:
        self.integral = 0.0
        self.last_error = None


@dataclass
class JointHandle:
    """One joint as the hardware interface sees it: state, and a command for its interface."""

    name: str
    interface: str
    effort_limit: float
    velocity_limit: float
    lower: float | None
    upper: float | None
    ref: JointRef | None = None
    actuator: int = -1
    pid: Pid | None = None
    motor: VelocityMotor | None = None
    """A velocity joint without PID gains: Gazebo's joint motor."""
    command: float | None = None
    position: float = 0.0
    velocity: float = 0.0
    effort: float = 0.0
    claimed_by: str | None = None


class Controller:
    """Base of the controllers: ``update(now_ns, dt)`` reads handles and sets commands."""

    interface: str | None = None

    def __init__(self, manager: ControllerManager, name: str, params: dict[str, Any]) -> None:
        self.manager = manager
        self.name = name
        self.params = params
        self.node = manager.graph.create_node(name, namespace=manager.namespace)
        self.running = False

    def joints(self) -> list[str]:
        return []

    def handle(self, joint: str) -> JointHandle:
        handle = self.manager.handles.get(joint)
        if handle is None:
            known = ", ".join(sorted(self.manager.handles)) or "none"
            msg = f"controller {self.name!r}: joint {joint!r} has no transmission (have: {known})"
            raise ModelError(msg)
        if self.interface is not None and handle.interface != self.interface:
            msg = (
                f"controller {self.name!r} needs a {self.interface} interface on {joint!r}, "
                f"but its transmission gives {handle.interface}"
            )
            raise ModelError(msg)
        return handle

    def start(self) -> None:
        self.running = True

    def stop(self) -> None:
        self.running = False

    def update(self, now_ns: int, dt: float) -> None: ...


class JointStateController(Controller):
    """joint_state_controller/JointStateController: every joint on ``joint_states``."""

    def __init__(self, manager: ControllerManager, name: str, params: dict[str, Any]) -> None:
        super().__init__(manager, name, params)
        rate = float(params.get("publish_rate", 50.0))
        self.publish_gate = RateGate(rate, manager.graph.now_ns(), strict=False, immediate=True)
        self.pub = manager.node.publisher("joint_states", "sensor_msgs/JointState", queue_size=10)

    def update(self, now_ns: int, dt: float) -> None:
        if not self.publish_gate.due(now_ns) or not self.pub.wanted:
            return
        handles = list(self.manager.handles.values())
        self.pub.publish(
            build.joint_state(
                now_ns,
                [h.name for h in handles],
                [h.position for h in handles],
                [h.velocity for h in handles],
                [h.effort for h in handles],
            )
        )


class ForwardCommand(Controller):
    """{position,velocity,effort}_controllers/Joint*Controller: ``command`` (Float64) is
    passed to the joint's interface."""

    def __init__(self, manager: ControllerManager, name: str, params: dict[str, Any]) -> None:
        super().__init__(manager, name, params)
        self.joint = _joint_param(name, params)
        self.target: float | None = None
        self.gate = CommandGate(self.node.resolve("~command"), manager.graph, logger)
        self.node.subscribe("~command", "std_msgs/Float64", self._on_command, queue_size=1)

    def joints(self) -> list[str]:
        return [self.joint]

    def _on_command(self, msg: Any) -> None:
        value = float(msg.data)
        if self.gate.accept(other={"data": value}):
            self.target = value

    def start(self) -> None:
        super().start()
        handle = self.handle(self.joint)
        if self.interface == "position" and self.target is None:
            self.target = handle.position  # hold where it is
        if self.target is None:
            self.target = 0.0

    def update(self, now_ns: int, dt: float) -> None:
        self.handle(self.joint).command = self.target


class EffortPid(ForwardCommand):
    """effort_controllers/JointPositionController and JointVelocityController: a PID from
    ``<controller>/pid`` turns the position (or velocity) error into an effort."""

    interface = "effort"

    def __init__(
        self, manager: ControllerManager, name: str, params: dict[str, Any], *, on: str
    ) -> None:
        super().__init__(manager, name, params)
        self.on = on
        pid = Pid.from_params(params.get("pid"))
        if pid is None:
            msg = (
                f"controller {name!r} ({params.get('type')}) needs PID gains: "
                f"{manager.namespace.rstrip('/')}/{name}/pid/p (and i, d)"
            )
            raise ModelError(msg)
        self.pid = pid

    def start(self) -> None:
        self.pid.reset()
        handle = self.handle(self.joint)
        if self.target is None:
            self.target = handle.position if self.on == "position" else 0.0
        self.running = True

    def update(self, now_ns: int, dt: float) -> None:
        handle = self.handle(self.joint)
        target = self.target or 0.0
        if self.on == "position":
            if handle.lower is not None and handle.upper is not None:
                target = min(max(target, handle.lower), handle.upper)
            error = target - handle.position
        else:
            error = target - handle.velocity
        handle.command = self.pid(error, dt)


class TrajectoryController(Controller):
    """{position,effort}_controllers/JointTrajectoryController: FollowJointTrajectory on
    ``<controller>/follow_joint_trajectory`` and JointTrajectory on ``<controller>/command``;
    linear interpolation between positions, cubic Hermite when velocities are given (as
    ros_controllers' splines; accelerations are not used); PID gains per joint under
    ``gains/<joint>`` for effort joints."""

    def __init__(
        self, manager: ControllerManager, name: str, params: dict[str, Any], *, interface: str
    ) -> None:
        super().__init__(manager, name, params)
        self.interface = interface
        joints = params.get("joints")
        if (
            not isinstance(joints, list)
            or not joints
            or not all(isinstance(j, str) for j in joints)
        ):
            msg = f"controller {name!r}: 'joints' must be a list of joint names"
            raise ModelError(msg)
        self.joint_list: list[str] = list(joints)
        self.pids: dict[str, Pid] = {}
        if interface == "effort":
            gains = params.get("gains", {})
            for joint in self.joint_list:
                pid = Pid.from_params(gains.get(joint) if isinstance(gains, dict) else None)
                if pid is None:
                    msg = f"controller {name!r}: no gains for joint {joint!r} (gains/{joint}/p)"
                    raise ModelError(msg)
                self.pids[joint] = pid
        self.segments: list[tuple[int, list[float], list[float], list[float]]] = []
        self.hold: list[float] = []
        self.goal: GoalHandle | None = None
        self.server = ActionServer(
            self.node,
            "~follow_joint_trajectory",
            "control_msgs/FollowJointTrajectory",
            self._on_goal,
        )
        self.node.subscribe("~command", "trajectory_msgs/JointTrajectory", self._on_command)
        self.state_pub = self.node.publisher(
            "~state", "control_msgs/JointTrajectoryControllerState", queue_size=1
        )

    def joints(self) -> list[str]:
        return list(self.joint_list)

    def start(self) -> None:
        super().start()
        self.hold = [self.handle(j).position for j in self.joint_list]
        for pid in self.pids.values():
            pid.reset()

    def _on_goal(self, goal: GoalHandle) -> None:
        problem = self._load(goal.goal.trajectory)
        if problem:
            goal.abort({"error_code": -2, "error_string": problem}, problem)
            return
        if self.goal is not None and self.goal is not goal:
            self.goal.preempted(text="replaced by a newer goal")
        self.goal = goal

    def _on_command(self, msg: Any) -> None:
        problem = self._load(msg)
        if problem:
            logger.error("%s/command: %s", self.name, problem)

    def _load(self, traj: Any) -> str | None:
        names = list(traj.joint_names)
        if sorted(names) != sorted(self.joint_list):
            return f"trajectory joints {names} do not match the controller's {self.joint_list}"
        order = [names.index(j) for j in self.joint_list]
        now = self.node.now_ns()
        stamp = traj.header.stamp
        start = stamp.sec * NS + stamp.nanosec or now
        current = [self.handle(j).position for j in self.joint_list]
        velocity = [self.handle(j).velocity for j in self.joint_list]
        segments = [(now, current, velocity, [0.0] * len(current))]
        for point in traj.points:
            positions = [float(point.positions[k]) for k in order] if len(point.positions) else []
            if len(positions) != len(order) or not all(math.isfinite(p) for p in positions):
                return "every point needs a finite position for each joint"
            vel = [float(point.velocities[k]) for k in order] if len(point.velocities) else []
            acc = [float(point.accelerations[k]) for k in order] if len(point.accelerations) else []
            t = start + point.time_from_start.sec * NS + point.time_from_start.nanosec
            segments.append((t, positions, vel, acc))
        segments = [s for i, s in enumerate(segments) if i == 0 or s[0] > now]
        self.segments = segments
        return None

    def desired(self, now_ns: int) -> list[float]:
        segments = self.segments
        if not segments:
            return self.hold
        if now_ns >= segments[-1][0]:
            self.hold = list(segments[-1][1])
            self.segments = []
            if self.goal is not None:
                self.goal.succeed({"error_code": 0})
                self.goal = None
            return self.hold
        for (t0, p0, v0, _), (t1, p1, v1, _) in itertools.pairwise(segments):
            if t0 <= now_ns < t1:
                span = (t1 - t0) / NS
                s = (now_ns - t0) / NS
                return [
                    _spline(p0[i], v0[i] if v0 else None, p1[i], v1[i] if v1 else None, span, s)
                    for i in range(len(p0))
                ]
        return self.hold

    def update(self, now_ns: int, dt: float) -> None:
        if self.goal is not None and self.goal.cancel_requested:
            self.hold = [self.handle(j).position for j in self.joint_list]
            self.segments = []
            self.goal.preempted(text="canceled")
            self.goal = None
        target = self.desired(now_ns)
        for joint, value in zip(self.joint_list, target, strict=True):
            handle = self.handle(joint)
            if self.interface == "effort":
                handle.command = self.pids[joint](value - handle.position, dt)
            else:
                handle.command = value
        if self.state_pub.wanted:
            actual = [self.handle(j).position for j in self.joint_list]
            self.state_pub.publish(
                message_from_data(
                    "control_msgs/JointTrajectoryControllerState",
                    {
                        "header": {"stamp": [now_ns // NS, now_ns % NS]},
                        "joint_names": self.joint_list,
                        "desired": {"positions": target},
                        "actual": {"positions": actual},
                        "error": {
                            "positions": [d - a for d, a in zip(target, actual, strict=True)]
                        },
                    },
                )
            )


def _spline(
    p0: float, v0: float | None, p1: float, v1: float | None, span: float, s: float
) -> float:
    if span <= 0:
        return p1
    if v0 is None or v1 is None:
        return p0 + (p1 - p0) * s / span
    # cubic Hermite through both positions with both velocities
    t = s / span
    h00 = 2 * t**3 - 3 * t**2 + 1
    h10 = t**3 - 2 * t**2 + t
    h01 = -2 * t**3 + 3 * t**2
    h11 = t**3 - t**2
    return h00 * p0 + h10 * span * v0 + h01 * p1 + h11 * span * v1


class DiffDriveController(Controller):
    """diff_drive_controller/DiffDriveController (velocity joints): ``cmd_vel`` with a
    timeout, odometry integrated "exactly" from wheel positions, ``odom`` and its TF."""

    interface = "velocity"

    def __init__(self, manager: ControllerManager, name: str, params: dict[str, Any]) -> None:
        super().__init__(manager, name, params)
        self.left = _names(params.get("left_wheel"), name, "left_wheel")
        self.right = _names(params.get("right_wheel"), name, "right_wheel")
        self.separation = float(params.get("wheel_separation", 0.0)) * float(
            params.get("wheel_separation_multiplier", 1.0)
        )
        self.radius = float(params.get("wheel_radius", 0.0)) * float(
            params.get("wheel_radius_multiplier", 1.0)
        )
        if self.separation <= 0 or self.radius <= 0:
            sep, rad = manager.wheel_geometry(self.left[0], self.right[0])
            self.separation = self.separation or sep
            self.radius = self.radius or rad
        self.timeout_ns = round(float(params.get("cmd_vel_timeout", 0.5)) * NS)
        rate = float(params.get("publish_rate", 50.0))
        self.publish_gate = RateGate(rate, manager.graph.now_ns(), strict=False, immediate=True)
        self.base_frame = str(params.get("base_frame_id", "base_link"))
        self.odom_frame = str(params.get("odom_frame_id", "odom"))
        self.enable_tf = bool(params.get("enable_odom_tf", True))
        self.pose_cov = _diagonal(params.get("pose_covariance_diagonal"))
        self.twist_cov = _diagonal(params.get("twist_covariance_diagonal"))
        self.limits = (
            params.get("linear", {}).get("x", {}) if isinstance(params.get("linear"), dict) else {}
        )
        self.angular_limits = (
            params.get("angular", {}).get("z", {})
            if isinstance(params.get("angular"), dict)
            else {}
        )
        self.cmd = (0.0, 0.0)
        self.cmd_ns = 0
        self.x = self.y = self.heading = 0.0
        self.last_wheels: tuple[float, float] | None = None
        self.velocity = (0.0, 0.0)
        self.gate = CommandGate(self.node.resolve("~cmd_vel"), manager.graph, logger)
        self.node.subscribe("~cmd_vel", "geometry_msgs/Twist", self._on_cmd, queue_size=1)
        self.odom_pub = self.node.publisher("~odom", "nav_msgs/Odometry", queue_size=100)
        self.tf = TransformBroadcaster(self.node)

    def joints(self) -> list[str]:
        return [*self.left, *self.right]

    def _on_cmd(self, msg: Any) -> None:
        v, w = float(msg.linear.x), float(msg.angular.z)
        if not self.gate.accept(linear={"linear.x": v}, angular={"angular.z": w}):
            return
        self.cmd = (_limit(v, self.limits), _limit(w, self.angular_limits))
        self.cmd_ns = self.node.now_ns()

    def update(self, now_ns: int, dt: float) -> None:
        left = sum(self.handle(j).position for j in self.left) / len(self.left)
        right = sum(self.handle(j).position for j in self.right) / len(self.right)
        if self.last_wheels is not None and dt > 0:
            dl = (left - self.last_wheels[0]) * self.radius
            dr = (right - self.last_wheels[1]) * self.radius
            linear, angular = (dl + dr) / 2, (dr - dl) / self.separation
            if abs(angular) < 1e-6:  # RK2
                direction = self.heading + angular / 2
                self.x += linear * math.cos(direction)
                self.y += linear * math.sin(direction)
                self.heading += angular
            else:  # exact arc
                r = linear / angular
                new_heading = self.heading + angular
                self.x += r * (math.sin(new_heading) - math.sin(self.heading))
                self.y -= r * (math.cos(new_heading) - math.cos(self.heading))
                self.heading = new_heading
            self.velocity = (linear / dt, angular / dt)
        self.last_wheels = (left, right)
        v, w = self.cmd if now_ns - self.cmd_ns <= self.timeout_ns else (0.0, 0.0)
        left_speed = (v - w * self.separation / 2) / self.radius
        right_speed = (v + w * self.separation / 2) / self.radius
        for j in self.left:
            self.handle(j).command = left_speed
        for j in self.right:
            self.handle(j).command = right_speed
        if not self.publish_gate.due(now_ns):
            return
        quat = (0.0, 0.0, math.sin(self.heading / 2), math.cos(self.heading / 2))
        position = (self.x, self.y, 0.0)
        if self.odom_pub.wanted:
            self.odom_pub.publish(
                build.odometry(
                    stamp_ns=now_ns,
                    frame_id=self.odom_frame,
                    child_frame_id=self.base_frame,
                    position=position,
                    quat_xyzw=quat,
                    linear=(self.velocity[0], 0.0, 0.0),
                    angular=(0.0, 0.0, self.velocity[1]),
                    pose_covariance=self.pose_cov,
                    twist_covariance=self.twist_cov,
                )
            )
        if self.enable_tf:
            self.tf.send(self.odom_frame, self.base_frame, position, quat, now_ns)


def _limit(value: float, limits: dict[str, Any]) -> float:
    if limits.get("has_velocity_limits"):
        top = float(limits.get("max_velocity", math.inf))
        bottom = float(limits.get("min_velocity", -top))
        return min(max(value, bottom), top)
    return value


def _diagonal(values: Any) -> list[float] | None:
    if not isinstance(values, list) or len(values) != 6:
        return None
    out = [0.0] * 36
    for i, v in enumerate(values):
        out[i * 7] = float(v)
    return out


def _names(value: Any, controller: str, key: str) -> list[str]:
    if isinstance(value, str):
        return [value]
    if isinstance(value, list) and value and all(isinstance(v, str) for v in value):
        return list(value)
    msg = f"controller {controller!r}: {key!r} must name a wheel joint (or a list of them)"
    raise ModelError(msg)


def _joint_param(controller: str, params: dict[str, Any]) -> str:
    joint = params.get("joint")
    if not isinstance(joint, str) or not joint:
        msg = f"controller {controller!r}: parameter 'joint' (the joint to command) is missing"
        raise ModelError(msg)
    return joint


def _forward(interface: str) -> Callable[[ControllerManager, str, dict[str, Any]], Controller]:
    def make(manager: ControllerManager, name: str, params: dict[str, Any]) -> Controller:
        controller = ForwardCommand(manager, name, params)
        controller.interface = interface
        return controller

    return make


CONTROLLER_TYPES: dict[str, Callable[[ControllerManager, str, dict[str, Any]], Controller]] = {
    "joint_state_controller/JointStateController": JointStateController,
    "position_controllers/JointPositionController": _forward("position"),
    "velocity_controllers/JointVelocityController": _forward("velocity"),
    "effort_controllers/JointEffortController": _forward("effort"),
    "effort_controllers/JointPositionController": lambda m, n, p: EffortPid(m, n, p, on="position"),
    "effort_controllers/JointVelocityController": lambda m, n, p: EffortPid(m, n, p, on="velocity"),
    "position_controllers/JointTrajectoryController": lambda m, n, p: TrajectoryController(
        m, n, p, interface="position"
    ),
    "effort_controllers/JointTrajectoryController": lambda m, n, p: TrajectoryController(
        m, n, p, interface="effort"
    ),
    "velocity_controllers/JointTrajectoryController": lambda m, n, p: TrajectoryController(
        m, n, p, interface="velocity"
    ),
    "diff_drive_controller/DiffDriveController": DiffDriveController,
}


@dataclass
class ControllerManager:
    """The controllers of one robot, and the services that load, start and stop them."""

    plugin: RosControl
    namespace: str
    handles: dict[str, JointHandle]
    controllers: dict[str, Controller] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.graph = self.plugin.ctx.graph
        self.node: Node = self.graph.create_node("controller_manager", namespace=self.namespace)
        for service, srv, handler in (
            ("load_controller", "LoadController", self._load),
            ("unload_controller", "UnloadController", self._unload),
            ("switch_controller", "SwitchController", self._switch),
            ("list_controllers", "ListControllers", self._list),
        ):
            self.node.service(
                f"controller_manager/{service}", f"controller_manager_msgs/{srv}", handler
            )

    def wheel_geometry(self, left: str, right: str) -> tuple[float, float]:
        return self.plugin.wheel_geometry(left, right)

    def load(self, name: str) -> Controller:
        if name in self.controllers:
            msg = f"controller {name!r} is already loaded"
            raise ModelError(msg)
        params = self.graph.params.get(f"{self.namespace.rstrip('/')}/{name}", None)
        if not isinstance(params, dict) or "type" not in params:
            msg = (
                f"controller {name!r}: no parameter {self.namespace.rstrip('/')}/{name}/type "
                "(load the controllers' YAML into the parameter server first)"
            )
            raise ModelError(msg)
        factory = CONTROLLER_TYPES.get(str(params["type"]))
        if factory is None:
            known = ", ".join(sorted(CONTROLLER_TYPES))
            msg = f"controller {name!r}: unknown type {params['type']!r} (known: {known})"
            raise ModelError(msg)
        controller = factory(self, name, params)
        for joint in controller.joints():
            controller.handle(joint)  # checks the joint and its interface now
        self.controllers[name] = controller
        return controller

    def start(self, name: str) -> None:
        controller = self.controllers[name]
        for joint in controller.joints():
            handle = controller.handle(joint)
            if handle.claimed_by not in (None, name):
                msg = (
                    f"controller {name!r}: joint {joint!r} is already claimed by "
                    f"{handle.claimed_by!r}"
                )
                raise ModelError(msg)
        for joint in controller.joints():
            controller.handle(joint).claimed_by = name
        controller.start()

    def stop(self, name: str) -> None:
        controller = self.controllers[name]
        controller.stop()
        for joint in controller.joints():
            handle = controller.handle(joint)
            if handle.claimed_by == name:
                handle.claimed_by = None
                handle.command = None

    def update(self, now_ns: int, dt: float) -> None:
        for controller in self.controllers.values():
            if controller.running:
                controller.update(now_ns, dt)

    # --- services --------------------------------------------------------------------------------
    def _load(self, req: Any) -> dict[str, Any]:
        try:
            self.load(req.name)
        except ModelError as err:
            logger.error("%s", err.message)
            return {"ok": False}
        return {"ok": True}

    def _unload(self, req: Any) -> dict[str, Any]:
        controller = self.controllers.get(req.name)
        if controller is None or controller.running:
            return {"ok": False}
        del self.controllers[req.name]
        return {"ok": True}

    def _switch(self, req: Any) -> dict[str, Any]:
        try:
            for name in req.stop_controllers:
                if name in self.controllers:
                    self.stop(name)
                elif req.strictness == 2:
                    return {"ok": False}
            for name in req.start_controllers:
                if name not in self.controllers:
                    if req.strictness == 2:
                        return {"ok": False}
                    continue
                self.start(name)
        except ModelError as err:
            logger.error("%s", err.message)
            return {"ok": False}
        return {"ok": True}

    def _list(self, _: Any) -> dict[str, Any]:
        def interface(c: Controller) -> str:
            # ros_control names the interface by its C++ type; a state controller reads the
            # JointStateInterface, which claims nothing
            if not c.interface:
                return "hardware_interface::JointStateInterface"
            return f"hardware_interface::{c.interface.capitalize()}JointInterface"

        return {
            "controller": [
                {
                    "name": name,
                    "state": "running" if c.running else "stopped",
                    "type": str(c.params.get("type", "")),
                    "claimed_resources": [
                        {
                            "hardware_interface": interface(c),
                            "resources": c.joints(),
                        }
                    ],
                }
                for name, c in self.controllers.items()
            ]
        }


class RosControl(Plugin):
    """``libgazebo_ros_control.so``: the robot's joints with transmissions, as a
    hardware interface, and its controller_manager."""

    NAMESPACE_DEFAULTS_TO_MODEL = True

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        sim_type = self.text("robotSimType")
        if sim_type and sim_type not in ("gazebo_ros_control/DefaultRobotHWSim", ""):
            logger.warning("%s: robotSimType %r: using DefaultRobotHWSim", ctx.source, sim_type)
        period = self.number("controlPeriod", 0.0)
        self.period_ns = round(period * NS) if period > 0 else 0
        self.last_ns: int | None = None
        self.handles = self._handles()
        ns = self.namespace()
        gains = ctx.graph.params.get(f"{ns.rstrip('/')}/gazebo_ros_control/pid_gains", {}) or {}
        missing = []
        for handle in self.handles.values():
            handle.pid = (
                Pid.from_params(gains.get(handle.name)) if isinstance(gains, dict) else None
            )
            if handle.pid is None and handle.interface != "effort":
                missing.append(handle.name)
        for handle in self.handles.values():
            if handle.interface == "velocity" and handle.pid is None:
                # Gazebo's joint motor: the velocity within the effort limit, as a constraint
                joint = self.robot.joints[handle.name]
                handle.motor = VelocityMotor(
                    self._actuator(handle.name), joint, handle.effort_limit
                )
        if missing:
            logger.warning(
                "ros_control: no PID gains for %s (%s/gazebo_ros_control/pid_gains/<joint>): "
                "velocity joints follow like Gazebo's joint motor, position joints like a stiff "
                "servo, within their effort limits",
                ", ".join(missing),
                ns.rstrip("/"),
            )
        unlimited = [h.name for h in self.handles.values() if not math.isfinite(h.effort_limit)]
        if unlimited:
            logger.warning(
                "ros_control: %s have no effort limit in the URDF: their commands are followed "
                "with any force (add <limit effort=…> for realistic starts and stops)",
                ", ".join(unlimited),
            )
        self.manager = ControllerManager(self, ns, self.handles)

    def _handles(self) -> dict[str, JointHandle]:
        handles: dict[str, JointHandle] = {}
        model = self.robot.model
        for transmission in model.transmissions:
            for tj in transmission.joints:
                interfaces = tj.hardware_interfaces or next(
                    (
                        a.hardware_interfaces
                        for a in transmission.actuators
                        if a.hardware_interfaces
                    ),
                    (),
                )
                kind = None
                for name in interfaces:
                    kind = INTERFACES.get(name.rsplit("/", 1)[-1])
                    if kind:
                        break
                if kind is None:
                    msg = (
                        f"transmission {transmission.name!r}: joint {tj.name!r} needs a "
                        "hardwareInterface (Effort-, Velocity- or PositionJointInterface)"
                    )
                    raise ModelError(msg, transmission.source.best)
                if tj.name not in self.robot.joints:
                    msg = f"transmission {transmission.name!r}: {tj.name!r} is not a movable joint"
                    raise ModelError(msg, transmission.source.best)
                joint = next(j for j in model.joints if j.name == tj.name)
                limit = joint.limit
                bounds = joint.position_range
                handles[tj.name] = JointHandle(
                    tj.name,
                    kind,
                    limit.effort if limit and limit.effort > 0 else math.inf,
                    limit.velocity if limit and limit.velocity > 0 else math.inf,
                    bounds[0] if bounds else None,
                    bounds[1] if bounds else None,
                )
        return handles

    def joint_names(self) -> tuple[str, ...]:
        # Reported once a joint_state_controller runs, which ros_control setups always spawn.
        return tuple(self.handles)

    def wheel_geometry(self, left: str, right: str) -> tuple[float, float]:
        """Wheel separation and radius from the URDF (diff_drive_controller's fallback)."""
        model = self.robot.model
        joints = {j.name: j for j in model.joints}
        if left not in joints or right not in joints:
            msg = f"diff_drive_controller: wheels {left!r}/{right!r} are not joints"
            raise ModelError(msg)
        poses = model.forward_kinematics()
        a, b = poses[joints[left].child], poses[joints[right].child]
        separation = float(((a[:3, 3] - b[:3, 3]) ** 2).sum() ** 0.5)
        collisions = model.link(joints[left].child).collisions
        radius = next((getattr(c.geometry, "radius", 0.0) for c in collisions), 0.0)
        if radius <= 0:
            msg = f"diff_drive_controller: give wheel_radius (wheel {left!r} has no cylinder)"
            raise ModelError(msg)
        return separation, float(radius)

    # --- model -----------------------------------------------------------------------------------
    def prepare(self, spec: mujoco.MjSpec) -> None:
        for handle in self.handles.values():
            if handle.motor is not None:
                handle.motor.add_to(spec)
                continue
            actuator = spec.add_actuator(name=self._actuator(handle.name))
            actuator.target = self.robot.joints[handle.name]
            actuator.trntype = mujoco.mjtTrn.mjTRN_JOINT
            if handle.interface == "position" and handle.pid is None:
                actuator.set_to_position(kp=2000.0, dampratio=1.0)
            else:
                actuator.set_to_motor()
            if math.isfinite(handle.effort_limit):
                actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
                actuator.forcerange = [-handle.effort_limit, handle.effort_limit]

    def _actuator(self, joint: str) -> str:
        return f"{self.robot.name}/ros_control/{joint}"

    def bind(self) -> None:
        for handle in self.handles.values():
            handle.ref = self.engine.joint(self.robot.joints[handle.name])
            handle.actuator = self.engine.actuator_id(self._actuator(handle.name))
            if handle.motor is not None:
                handle.motor.bind(self.engine)
                handle.motor.apply(self.engine)

    def update(self, now_ns: int) -> None:
        for h in self.handles.values():
            if h.motor is not None:
                h.motor.apply(self.engine)
        if self.last_ns is not None and self.period_ns and now_ns - self.last_ns < self.period_ns:
            return
        dt = (now_ns - self.last_ns) / NS if self.last_ns is not None else 0.0
        self.last_ns = now_ns
        d = self.engine.d
        for h in self.handles.values():
            assert h.ref is not None
            h.position = float(d.qpos[h.ref.qpos])
            h.velocity = float(d.qvel[h.ref.dof])
            h.effort = float(d.actuator_force[h.actuator])
        self.manager.update(now_ns, dt)
        for h in self.handles.values():
            if h.motor is not None:
                h.motor.command(self._control(h, dt))
                h.motor.apply(self.engine)
            else:
                d.ctrl[h.actuator] = self._control(h, dt)

    def _control(self, h: JointHandle, dt: float) -> float:
        if h.command is None:
            # nothing commands it: hold still (velocity 0 / current position / no effort)
            if h.interface == "velocity" and h.pid is None:
                return 0.0
            if h.interface == "position" and h.pid is None:
                return h.position
            return 0.0
        command = h.command
        if h.interface == "effort":
            return min(max(command, -h.effort_limit), h.effort_limit)
        if h.interface == "velocity":
            command = min(max(command, -h.velocity_limit), h.velocity_limit)
            if h.pid is None:
                return command
            return h.pid(command - h.velocity, dt)
        if h.lower is not None and h.upper is not None:
            command = min(max(command, h.lower), h.upper)
        if h.pid is None:
            return command
        return h.pid(command - h.position, dt)

    def reset(self) -> None:
        for controller in self.manager.controllers.values():
            if controller.running:
                controller.start()


def spawner(node: Node, argv: list[str], *, namespace: str = "/") -> list[str]:
    """``controller_manager spawner NAME…``: load and start controllers (``--stopped``: load
    only; ``--namespace NS``). Returns the names started."""
    names: list[str] = []
    stopped = False
    ns = namespace
    words = list(argv)
    while words:
        word = words.pop(0)
        if word == "--stopped":
            stopped = True
        elif word in ("--namespace", "--timeout"):
            value = words.pop(0) if words else ""
            if word == "--namespace":
                ns = value
        elif word.startswith("--namespace="):
            ns = word.split("=", 1)[1]
        elif word.startswith("--") or word == "--shutdown-timeout":
            continue
        else:
            names.append(word)
    base = "/" + "/".join(p for p in ns.split("/") if p)
    prefix = base.rstrip("/") + "/controller_manager"
    for name in names:
        ok = node.call_service(
            f"{prefix}/load_controller", "controller_manager_msgs/LoadController", {"name": name}
        )
        if not ok.ok:
            msg = f"spawner: failed to load controller {name!r} (see the error above)"
            raise ModelError(msg)
    if not stopped and names:
        ok = node.call_service(
            f"{prefix}/switch_controller",
            "controller_manager_msgs/SwitchController",
            {"start_controllers": names, "stop_controllers": [], "strictness": 2},
        )
        if not ok.ok:
            msg = f"spawner: failed to start controllers {names}"
            raise ModelError(msg)
    return names
