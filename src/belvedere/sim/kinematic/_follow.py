"""``follow_controller``: a FollowJointTrajectory action (and a ``<name>/command``
JointTrajectory topic) over servo joints, executed as the original does.

Per point: with a ``time_from_start`` the joints move together so they arrive at that time;
without one, each joint moves at its point velocity. Every ``1/rate`` seconds each joint's target
steps towards the point by at most the speed that still arrives on time, and the servos then
follow at their own ``max_speed``. A newer goal or a cancel preempts the running one.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any

from belvedere.graph import NS, ActionServer, GoalHandle, Node, Timer
from belvedere.sim.kinematic._config import FollowControllerConfig
from belvedere.sim.kinematic._servos import Servo

__all__ = ["FollowController"]

logger = logging.getLogger("belvedere.arbotix")

_LEAD_NS = 10_000_000  # the original's 0.01 s look-ahead when waiting and stepping
_DEADBAND = 0.001  # rad: closer than this, a joint is not moved (as the original)


class _TrajectoryError(Exception):
    """The trajectory cannot be executed (the original returns -1)."""


@dataclass
class _Run:
    """One trajectory being executed."""

    points: list[Any]
    indexes: list[int]
    start_ns: int
    handle: GoalHandle | None
    timer: Timer | None = None
    point: int = 0
    end_ns: int | None = None
    desired: list[float] = field(default_factory=list)
    sync: bool = True
    last: list[float] = field(default_factory=list)


class FollowController:
    """A joint-trajectory controller for some of the driver's servos."""

    joint_names: tuple[str, ...] = ()  # the servos themselves report on joint_states
    joint_positions: tuple[float, ...] = ()
    joint_velocities: tuple[float, ...] = ()

    def __init__(self, node: Node, config: FollowControllerConfig, servos: dict[str, Servo]):
        self.node = node
        self.config = config
        self.name = config.name
        self.joints = list(config.joints)
        self.servos = [servos[j] for j in self.joints]
        for servo in self.servos:
            servo.controller = self
        self.run: _Run | None = None
        self.server = ActionServer(
            node, config.action_name, "control_msgs/FollowJointTrajectory", self._on_goal
        )
        node.subscribe(f"{self.name}/command", "trajectory_msgs/JointTrajectory", self._on_command)
        logger.info("Started FollowController (%s). Joints: %s", self.name, self.joints)

    def active(self) -> bool:
        return self.run is not None

    # --- inputs --------------------------------------------------------------------------------
    def _on_goal(self, handle: GoalHandle) -> None:
        traj = handle.goal.trajectory
        names = list(traj.joint_names)
        missing = [j for j in self.joints if j not in names]
        if missing:
            text = (
                "Trajectory joint names does not match action controlled joints: "
                f"{names} (missing {missing})"
            )
            logger.error("%s: %s", self.name, text)
            handle.abort({"error_code": -2, "error_string": text}, text)
            return
        if set(names) != set(self.joints):
            logger.warning("%s: extra joints in trajectory %s", self.name, names)
        if not traj.points:
            text = "Trajectory empty."
            logger.error("%s: %s", self.name, text)
            handle.abort({"error_code": -1, "error_string": text}, text)
            return
        self._start(traj, handle)

    def _on_command(self, msg: Any) -> None:
        if self.server.current is not None:
            logger.info("%s: received a trajectory, but an action is active", self.name)
            return
        names = list(msg.joint_names)
        if any(j not in names for j in self.joints):
            logger.error("%s: invalid joint in trajectory %s", self.name, names)
            return
        if msg.points:
            self._start(msg, None)

    # --- execution -----------------------------------------------------------------------------
    def _start(self, traj: Any, handle: GoalHandle | None) -> None:
        if self.run is not None:  # a topic trajectory replaced by an action goal
            self._end(self.run, preempted=True)
        names = list(traj.joint_names)
        stamp = traj.header.stamp
        start = stamp.sec * NS + stamp.nanosec or self.node.now_ns()
        run = _Run(
            points=list(traj.points),
            indexes=[names.index(j) for j in self.joints],
            start_ns=start,
            handle=handle,
            last=[s.position for s in self.servos],
        )
        self.run = run
        run.timer = self.node.timer(1.0 / self.config.rate, lambda: self._step(run))
        self._step(run)

    def _step(self, run: _Run) -> None:
        if run is not self.run:
            return
        if run.handle is not None and run.handle.cancel_requested:
            self._end(run, preempted=True)
            return
        now = self.node.now_ns()
        try:
            while True:
                if run.end_ns is None:
                    if run.point == len(run.points):
                        self._end(run)
                        return
                    if now + _LEAD_NS < run.start_ns:
                        return  # waiting for the trajectory's start time
                    self._begin_point(run, now)
                assert run.end_ns is not None
                if now + _LEAD_NS < run.end_ns:
                    self._move(run, now)
                    return
                run.point += 1
                run.end_ns = None
        except _TrajectoryError as err:
            logger.error("%s: %s", self.name, err)
            self._end(run, failed=str(err))

    def _begin_point(self, run: _Run, now: int) -> None:
        point = run.points[run.point]
        try:
            run.desired = [float(point.positions[k]) for k in run.indexes]
        except IndexError:
            msg = f"point {run.point} has {len(point.positions)} positions"
            raise _TrajectoryError(msg) from None
        tfs = point.time_from_start
        tfs_ns = tfs.sec * NS + tfs.nanosec
        if tfs_ns > 0:
            run.sync = True
            run.end_ns = run.start_ns + tfs_ns
            return
        run.sync = False
        if len(point.velocities) != len(self.joints):
            msg = (
                "Invalid joint in trajectory: Specify either time_from_start or velocity "
                "profiles for each intermediate goal."
            )
            raise _TrajectoryError(msg)
        speeds = [abs(float(point.velocities[k])) for k in run.indexes]
        errors = [d - c for d, c in zip(run.desired, run.last, strict=True)]
        if any(e != 0 and v <= 0 for e, v in zip(errors, speeds, strict=True)):
            msg = "Specifying a nonzero joint transition with zero velocity is not possible."
            raise _TrajectoryError(msg)
        durations = [abs(e / v) for e, v in zip(errors, speeds, strict=True) if v > 0]
        # As the original: the end time counts from the trajectory's start, not from now.
        run.end_ns = run.start_ns + round(max(durations, default=0.0) * NS)

    def _move(self, run: _Run, now: int) -> None:
        assert run.end_ns is not None
        point = run.points[run.point]
        rate = self.config.rate
        remaining = (run.end_ns - now) / NS
        for i, servo in enumerate(self.servos):
            err = run.desired[i] - run.last[i]
            if abs(err) <= _DEADBAND:
                continue
            if run.sync:
                top = abs(err / (rate * remaining))
            else:
                top = abs(float(point.velocities[run.indexes[i]])) / rate
            run.last[i] += min(max(err, -top), top)
            servo.set_control_output(run.last[i])

    def _end(self, run: _Run, *, preempted: bool = False, failed: str | None = None) -> None:
        if run.timer is not None:
            run.timer.cancel()
        if self.run is run:
            self.run = None
        handle = run.handle
        if handle is None:
            return
        if failed is not None:
            handle.abort({"error_code": -1, "error_string": failed}, "Execution failed.")
        elif preempted:
            handle.preempted(text="Goal canceled.")
        else:
            handle.succeed({"error_code": 0}, "")
            logger.info("%s: Done.", self.name)

    def reset(self) -> None:
        """Stop the running trajectory (its goal is preempted)."""
        if self.run is not None:
            self._end(self.run, preempted=True)

    def diagnostics(self) -> dict[str, Any]:
        state = "Active" if self.active() else "Not Active"
        return {
            "name": self.name,
            "level": 0,
            "message": "OK",
            "values": [{"key": "State", "value": state}],
        }
