"""ros_controllers' joint controllers: the state publisher, forward commands, effort PIDs and
the joint trajectory controller."""

from __future__ import annotations

import itertools
import logging
import math
from typing import Any

from belvedere.graph import NS, ActionServer, GoalHandle
from belvedere.msgs import build, message_from_data
from belvedere.sim._commands import CommandGate
from belvedere.sim.physics._plugin import RateGate
from belvedere.sim.physics._ros_control._hardware import ControllerHost, JointHandle, Pid
from belvedere.sim.physics._spec import ModelError

__all__ = [
    "Controller",
    "EffortPid",
    "ForwardCommand",
    "JointStateController",
    "TrajectoryController",
]

logger = logging.getLogger("belvedere.ros_control")


class Controller:
    """Base of the controllers: ``update(now_ns, dt)`` reads handles and sets commands."""

    interface: str | None = None

    def __init__(self, manager: ControllerHost, name: str, params: dict[str, Any]) -> None:
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

    def __init__(self, manager: ControllerHost, name: str, params: dict[str, Any]) -> None:
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

    def __init__(self, manager: ControllerHost, name: str, params: dict[str, Any]) -> None:
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
        self, manager: ControllerHost, name: str, params: dict[str, Any], *, on: str
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
        self, manager: ControllerHost, name: str, params: dict[str, Any], *, interface: str
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


def _joint_param(controller: str, params: dict[str, Any]) -> str:
    joint = params.get("joint")
    if not isinstance(joint, str) or not joint:
        msg = f"controller {controller!r}: parameter 'joint' (the joint to command) is missing"
        raise ModelError(msg)
    return joint
