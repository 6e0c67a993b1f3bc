"""move_base: the ``move_base`` action over two costmaps, a global and a local planner, and
the recovery behaviours, as ROS 1's move_base runs them.

In: goals on the ``move_base`` action (``move_base_msgs/MoveBaseAction``) and on
``move_base_simple/goal``; the robot's pose from TF (each costmap's global frame → its
``robot_base_frame``); its velocity from ``odom``. Out: ``cmd_vel``, ``~current_goal``, the
global plan (``~<Planner>/plan``), the local planner's ``~<Planner>/local_plan`` and
``global_plan``, the costmaps (``~global_costmap/…``, ``~local_costmap/…``); services
``~make_plan`` and ``~clear_costmaps``.

Each control cycle (``controller_frequency``, graph time) follows move_base's states:
planning (a plan from the robot to the goal; none for ``planner_patience`` → recoveries),
controlling (the local planner's command, the goal reached within its tolerances → succeeded;
no command for ``controller_patience`` or no progress of ``oscillation_distance`` in
``oscillation_timeout`` → recoveries) and clearing (``~recovery_behaviors``, a list of
``{name, type}`` with each behaviour's parameters under ``~<name>/``; by default conservative
reset, rotate_recovery's turn in place if ``clearing_rotation_allowed``, aggressive reset,
the turn again; all tried → aborted). With
``planner_frequency`` > 0 the plan is remade that often while controlling. The planners run on
the graph's executor thread: in simulated time nothing moves while they think, so runs are
deterministic.
"""

from __future__ import annotations

import contextlib
import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.errors import BelvedereError
from belvedere.graph import NS, ActionServer, GoalHandle, Node
from belvedere.msgs import build, message_from_data, types
from belvedere.nav.local import (
    Command,
    LocalPlanner,
    NoTrajectoryError,
    TrajectoryPlannerROS,
    make_local_planner,
)
from belvedere.nav.planners import (
    GlobalPlanner,
    NoPathError,
    UnknownPluginError,
    make_global_planner,
)
from belvedere.nav.recovery import (
    ROTATE,
    ClearCostmapParams,
    RecoveryListError,
    RotateOutcome,
    RotateRecovery,
    RotateRecoveryParams,
    recovery_behaviors,
)
from belvedere.nodes._costmap import Costmap2DROS
from belvedere.nodes._registry import (
    NodeSpec,
    Session,
    Starter,
    StartError,
    stopping_on_bad_values,
)
from belvedere.tf import TFBuffer, TFError, TransformListener
from belvedere.yamlfile import load_yaml_file

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE", "MoveBaseParams"]

PACKAGE = "move_base"

logger = logging.getLogger("belvedere.nodes.move_base")

Floats = npt.NDArray[np.float64]


@dataclass(frozen=True)
class MoveBaseParams:
    """move_base's own parameters, with its defaults."""

    base_global_planner: str = "navfn/NavfnROS"
    base_local_planner: str = "base_local_planner/TrajectoryPlannerROS"
    controller_frequency: float = 20.0
    planner_frequency: float = 0.0
    planner_patience: float = 5.0
    controller_patience: float = 15.0
    max_planning_retries: int = -1
    oscillation_timeout: float = 0.0
    oscillation_distance: float = 0.5
    recovery_behavior_enabled: bool = True
    clearing_rotation_allowed: bool = True
    shutdown_costmaps: bool = False
    conservative_reset_dist: float = 3.0

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> MoveBaseParams:
        fields: dict[str, Any] = {}
        for name, default in cls().__dict__.items():
            if name not in values:
                continue
            value = values[name]
            if isinstance(default, bool):
                if not isinstance(value, bool):
                    message = f"parameter {name} must be true or false, got {value!r}"
                    raise ValueError(message)
            elif isinstance(default, int | float):
                if isinstance(value, bool) or not isinstance(value, int | float):
                    message = f"parameter {name} must be a number, got {value!r}"
                    raise ValueError(message)
                value = type(default)(value)
            else:
                value = str(value)
            fields[name] = value
        params = cls(**fields)
        if params.controller_frequency <= 0:
            message = "parameter controller_frequency must be positive"
            raise ValueError(message)
        return params


class _State(Enum):
    PLANNING = "planning"
    CONTROLLING = "controlling"
    CLEARING = "clearing"


class _Trigger(Enum):
    """What sent move_base to its recoveries last; only progress of that kind (a plan, a
    command, or moving ``oscillation_distance``) starts the recoveries over."""

    PLANNING = "planning"
    CONTROLLING = "controlling"
    OSCILLATION = "oscillation"


def _short(plugin: str) -> str:
    """A plugin's parameter namespace: ``navfn/NavfnROS`` → ``NavfnROS``."""
    return plugin.rsplit("/", 1)[-1]


def _pose_data(x: float, y: float, yaw: float) -> dict[str, Any]:
    """A planar pose as ``geometry_msgs/Pose`` data."""
    return {
        "position": {"x": float(x), "y": float(y), "z": 0.0},
        "orientation": {"z": math.sin(yaw / 2), "w": math.cos(yaw / 2)},
    }


def _yaw(q: Any) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def _transform(poses: Floats, transform: tuple[float, float, float]) -> npt.NDArray[np.float64]:
    """(N, 3) poses moved by a planar transform (x, y, yaw)."""
    x, y, th = transform
    c, s = math.cos(th), math.sin(th)
    out = np.empty_like(poses)
    out[:, 0] = x + c * poses[:, 0] - s * poses[:, 1]
    out[:, 1] = y + s * poses[:, 0] + c * poses[:, 1]
    out[:, 2] = poses[:, 2] + th
    return out


class _MoveBase:
    def __init__(self, node: Node, session: Session, spec: NodeSpec) -> None:
        self.node = node
        private = node.get_param("~", {})
        self.params = MoveBaseParams.from_mapping(private if isinstance(private, dict) else {})
        p = self.params
        self.buffer = TFBuffer()
        TransformListener(node, self.buffer)
        self.global_costmap = Costmap2DROS(node, "global_costmap", self.buffer)
        self.local_costmap = Costmap2DROS(node, "local_costmap", self.buffer)
        self.global_planner = self._plugin(session, spec, "base_global_planner", private)
        self.local_planner = self._plugin(session, spec, "base_local_planner", private)
        global_name, local_name = _short(p.base_global_planner), _short(p.base_local_planner)
        self.cmd_pub = node.publisher("cmd_vel", "geometry_msgs/Twist", queue_size=1)
        self.goal_pub = node.publisher("~current_goal", "geometry_msgs/PoseStamped", queue_size=1)
        self.plan_pub = node.publisher(f"~{global_name}/plan", "nav_msgs/Path", queue_size=1)
        self.local_plan_pub = node.publisher(
            f"~{local_name}/local_plan", "nav_msgs/Path", queue_size=1
        )
        self.followed_pub = node.publisher(
            f"~{local_name}/global_plan", "nav_msgs/Path", queue_size=1
        )
        self.velocity = np.zeros(3)
        node.subscribe("odom", "nav_msgs/Odometry", self._on_odom, queue_size=1)
        self.server = ActionServer(node, "move_base", "move_base_msgs/MoveBase", self._execute)
        self.goal_client = node.publisher(
            "move_base/goal", "move_base_msgs/MoveBaseActionGoal", queue_size=1
        )
        node.subscribe("move_base_simple/goal", "geometry_msgs/PoseStamped", self._on_simple_goal)
        node.service("~make_plan", "nav_msgs/GetPlan", self._on_make_plan)
        node.service("~clear_costmaps", "std_srvs/Empty", self._on_clear_costmaps)
        self.handle: GoalHandle | None = None
        self.goal: Floats | None = None
        self.state = _State.PLANNING
        self.plan: Floats | None = None
        self.plan_to_local: tuple[float, float, float] | None = None
        self.recovery_index = 0
        self.recovery_trigger = _Trigger.PLANNING
        self.planning_since = 0
        self.last_valid_control = 0
        self.last_plan_at = 0
        self.retries = 0
        self.oscillation_pose: Floats | None = None
        self.oscillation_since = 0
        self.rotation: RotateRecovery | None = None
        self.rotating = ""
        self.recoveries = self._recoveries(
            session, spec, private if isinstance(private, dict) else {}
        )
        self._warned: set[str] = set()
        self.global_costmap.start()
        self.local_costmap.start()
        if p.shutdown_costmaps:
            self.global_costmap.stop()
            self.local_costmap.stop()
        node.timer(1.0 / p.controller_frequency, self._cycle)

    def _plugin(self, session: Session, spec: NodeSpec, param: str, private: Any) -> Any:
        p = self.params
        name = p.base_global_planner if param == "base_global_planner" else p.base_local_planner
        values = private.get(_short(name), {}) if isinstance(private, dict) else {}
        values = values if isinstance(values, dict) else {}
        try:
            if param == "base_global_planner":
                planner: GlobalPlanner | LocalPlanner = make_global_planner(name, values)
            else:
                merged = {"controller_frequency": p.controller_frequency, **values}
                planner = make_local_planner(name, merged)
        except UnknownPluginError as err:
            where = session.param_source(f"{spec.full_name}/{param}") or spec.source
            message = f"{spec.full_name}: parameter {param}: {err}"
            raise StartError(message, where) from None
        return planner

    def _recoveries(
        self, session: Session, spec: NodeSpec, private: Mapping[str, Any]
    ) -> list[tuple[str, ClearCostmapParams | RotateRecoveryParams]]:
        """The recovery behaviours in the order move_base runs them, each with its
        parameters (``~<name>/``): ``~recovery_behaviors`` when given, else move_base's
        defaults (conservative reset, a turn if ``clearing_rotation_allowed``, aggressive
        reset, the turn again)."""
        blp = private.get("TrajectoryPlannerROS", {})
        blp = blp if isinstance(blp, dict) else {}

        def own(name: str) -> dict[str, Any]:
            values = private.get(name, {})
            return values if isinstance(values, dict) else {}

        if "recovery_behaviors" not in private:
            rotate = RotateRecoveryParams.from_mapping(own("rotate_recovery"), blp)
            clearing = self._clearing_params(private)
            turn: list[tuple[str, ClearCostmapParams | RotateRecoveryParams]] = (
                [("rotate_recovery", rotate)] if self.params.clearing_rotation_allowed else []
            )
            return [
                ("conservative_reset", clearing["conservative_reset"]),
                *turn,
                ("aggressive_reset", clearing["aggressive_reset"]),
                *turn,
            ]
        try:
            listed = recovery_behaviors(private["recovery_behaviors"])
        except RecoveryListError as err:
            where = session.param_source(f"{spec.full_name}/recovery_behaviors") or spec.source
            if where is not None and where.path.endswith((".yaml", ".yml")) and err.keys:
                # (a file changed since the launch read it keeps the list's line)
                with contextlib.suppress(BelvedereError):
                    where = load_yaml_file(where.path).location_within(where, *err.keys)
            message = f"{spec.full_name}: parameter {err}"
            raise StartError(message, where) from None
        out: list[tuple[str, ClearCostmapParams | RotateRecoveryParams]] = []
        for behaviour in listed:
            if behaviour.type == ROTATE:
                out.append(
                    (behaviour.name, RotateRecoveryParams.from_mapping(own(behaviour.name), blp))
                )
            else:
                out.append(
                    (
                        behaviour.name,
                        ClearCostmapParams.from_mapping(behaviour.name, own(behaviour.name)),
                    )
                )
        return out

    def _clearing_params(self, private: Mapping[str, Any]) -> dict[str, ClearCostmapParams]:
        """The two default clearing recoveries' parameters. As move_base does for its
        defaults, their ``reset_distance`` is ``conservative_reset_dist`` and four times
        ``~local_costmap/circumscribed_radius`` (a parameter of its own, default 0.46 m, not
        the costmap's radius)."""
        local = private.get("local_costmap", {})
        radius = local.get("circumscribed_radius", 0.46) if isinstance(local, dict) else 0.46
        if isinstance(radius, bool) or not isinstance(radius, int | float):
            message = (
                f"parameter local_costmap/circumscribed_radius must be a number, got {radius!r}"
            )
            raise ValueError(message)
        distances = {
            "conservative_reset": self.params.conservative_reset_dist,
            "aggressive_reset": 4.0 * float(radius),
        }
        out = {}
        for name, distance in distances.items():
            own = private.get(name, {})
            out[name] = ClearCostmapParams.from_mapping(
                name, own if isinstance(own, dict) else {}, distance
            )
        return out

    # --- inputs ------------------------------------------------------------------------------
    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            logger.warning("%s: %s", self.node.full_name, text)

    def _on_odom(self, msg: Any) -> None:
        t = msg.twist.twist
        self.velocity = np.array([t.linear.x, t.linear.y, t.angular.z])

    def _on_simple_goal(self, msg: Any) -> None:
        # as move_base: a simple goal becomes a goal on its own action
        now = self.node.now_ns()
        goal = message_from_data(
            "move_base_msgs/MoveBaseActionGoal",
            {
                "header": {"stamp": {"sec": now // NS, "nanosec": now % NS}},
                "goal_id": {"id": f"{self.node.full_name}-simple-{now}"},
            },
        )
        goal.goal.target_pose = msg
        self.goal_client.publish(goal)

    def _execute(self, handle: GoalHandle) -> None:
        target = handle.goal.target_pose
        goal = self._in_global_frame(target)
        if goal is None:
            handle.abort(text="the goal's frame cannot be transformed to the global frame")
            return
        self.handle = handle
        self.goal = goal
        self._publish_goal()
        self._start_planning()
        self.recovery_index = 0
        self.oscillation_pose = None

    def _in_global_frame(self, pose_stamped: Any) -> Floats | None:
        frame = pose_stamped.header.frame_id.lstrip("/") or self.global_costmap.global_frame
        p, q = pose_stamped.pose.position, pose_stamped.pose.orientation
        if not all(math.isfinite(v) for v in (p.x, p.y, q.x, q.y, q.z, q.w)):
            self._warn_once("nan", "a goal with NaN or infinite values was refused")
            return None
        if abs(math.sqrt(q.x**2 + q.y**2 + q.z**2 + q.w**2) - 1.0) > 0.01:
            self._warn_once("quat", "a goal whose orientation is not a unit quaternion was refused")
            return None
        pose: Floats = np.array([[p.x, p.y, _yaw(q)]], dtype=np.float64)
        if frame == self.global_costmap.global_frame:
            same: Floats = pose[0].copy()
            return same
        moved = self._planar(self.global_costmap.global_frame, frame)
        if moved is None:
            return None
        placed: Floats = _transform(pose, moved)[0]
        return placed

    def _planar(self, target: str, source: str) -> tuple[float, float, float] | None:
        try:
            _, t, q = self.buffer.lookup(target, source, 0)
        except TFError as err:
            self._warn_once(f"tf {target} {source}", err.message)
            return None
        x, y, z, w = q
        yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
        return (float(t[0]), float(t[1]), yaw)

    # --- the cycle ---------------------------------------------------------------------------
    def _start_planning(self) -> None:
        self.state = _State.PLANNING
        self.planning_since = self.node.now_ns()
        self.last_valid_control = self.node.now_ns()
        self.retries = 0
        self.oscillation_since = self.node.now_ns()

    def _cycle(self) -> None:
        handle = self.handle
        if handle is None:
            return
        if handle.cancel_requested:
            self._stop()
            self._end(lambda: handle.preempted(text="a newer goal or a cancel"))
            return
        if self.params.shutdown_costmaps and self.global_costmap.stopped:
            self.global_costmap.start()
            self.local_costmap.start()
        now = self.node.now_ns()
        pose = self.global_costmap.robot_pose()
        if pose is not None:
            header = {
                "stamp": {"sec": now // NS, "nanosec": now % NS},
                "frame_id": self.global_costmap.global_frame,
            }
            base_position = {"header": header, "pose": _pose_data(*pose)}
            handle.publish_feedback({"base_position": base_position})
            self._note_progress(pose, now)
        if self.state is _State.PLANNING:
            self._plan_step(now)
        elif self.state is _State.CONTROLLING:
            self._control_step(now)
        else:
            self._clearing_step(now)

    def _plan_step(self, now: int) -> None:
        if self._make_plan():
            self.state = _State.CONTROLLING
            self.last_valid_control = now
            if self.recovery_trigger is _Trigger.PLANNING:
                self.recovery_index = 0
            return
        self.retries += 1
        p = self.params
        out_of_patience = now - self.planning_since > round(p.planner_patience * NS)
        out_of_retries = 0 <= p.max_planning_retries < self.retries
        if out_of_patience or out_of_retries:
            self._stop()
            self._recover("failed to find a valid plan", _Trigger.PLANNING)

    def _make_plan(self) -> bool:
        pose = self.global_costmap.robot_pose()
        if pose is None or self.goal is None:
            return False
        self.global_costmap.update_now()
        try:
            plan = self.global_planner.plan(self.global_costmap.grid(), pose, self.goal)
        except NoPathError as err:
            self._warn_once("plan", f"no plan: {err}")
            return False
        self.plan = plan
        self.last_plan_at = self.node.now_ns()
        self.plan_to_local = None
        self._publish_path(self.plan_pub, plan, self.global_costmap.global_frame)
        self._hand_plan_to_local()
        return True

    def _hand_plan_to_local(self) -> bool:
        """Give the local planner the plan in its costmap's frame (again when that frame
        moved against the global one by more than a centimetre or a hundredth radian)."""
        assert self.plan is not None
        moved = self._planar(self.local_costmap.global_frame, self.global_costmap.global_frame)
        if moved is None:
            return False
        last = self.plan_to_local
        if last is not None and (
            math.hypot(moved[0] - last[0], moved[1] - last[1]) < 0.01
            and abs(math.remainder(moved[2] - last[2], math.tau)) < 0.01
        ):
            return True
        self.plan_to_local = moved
        self._check_goal_tolerance()
        local = _transform(self.plan, moved)
        self.local_planner.set_plan(local)
        self._publish_path(self.followed_pub, local, self.local_costmap.global_frame)
        return True

    def _check_goal_tolerance(self) -> None:
        """TrajectoryPlannerROS scores a trajectory by the cell it ends in, so every in-place
        turn in the goal's cell costs the same as being there: a robot that stops in that cell
        outside ``xy_goal_tolerance`` can turn in place for good. Warn when the tolerance does
        not cover the cell (a goal on a cell's corner is a diagonal away from its far one)."""
        if not isinstance(self.local_planner, TrajectoryPlannerROS):
            return
        tolerance = self.local_planner.params.xy_goal_tolerance
        resolution = self.local_costmap.costmap.master.resolution
        if tolerance < resolution * math.sqrt(2.0):
            self._warn_once(
                "tolerance",
                f"TrajectoryPlannerROS/xy_goal_tolerance {tolerance:g} m is less than a local "
                f"costmap cell's diagonal ({resolution * math.sqrt(2.0):.3f} m at "
                f"{resolution:g} m/cell): the robot may stop in the goal's cell outside the "
                "tolerance and turn in place there until oscillation_timeout or forever",
            )

    def _control_step(self, now: int) -> None:
        p = self.params
        if p.planner_frequency > 0 and now - self.last_plan_at >= round(NS / p.planner_frequency):
            self._make_plan()
        pose = self.local_costmap.robot_pose()
        if pose is None or not self._hand_plan_to_local():
            self._stop()
            return
        if p.oscillation_timeout > 0 and now - self.oscillation_since > round(
            p.oscillation_timeout * NS
        ):
            self._stop()
            self._recover("the robot is oscillating", _Trigger.OSCILLATION)
            return
        self.local_costmap.update_now()
        if self.local_planner.goal_reached(pose, self.velocity):
            self._stop()
            handle = self.handle
            assert handle is not None
            self._end(lambda: handle.succeed(text="Goal reached."))
            return
        try:
            command: Command = self.local_planner.compute(
                self.local_costmap.grid(), pose, self.velocity, self.local_costmap.footprint()
            )
        except NoTrajectoryError as err:
            self._stop()
            if now - self.last_valid_control > round(p.controller_patience * NS):
                self._recover(
                    f"the local planner found no valid command ({err})", _Trigger.CONTROLLING
                )
            else:
                self._start_planning_keep_patience()
            return
        self.last_valid_control = now
        if self.recovery_trigger is _Trigger.CONTROLLING:
            self.recovery_index = 0
        self._send(command.vx, command.vy, command.vth)
        self._publish_path(self.local_plan_pub, command.local_plan, self.local_costmap.global_frame)
        if self.local_planner.goal_reached(pose, self.velocity):
            self._stop()
            handle = self.handle
            assert handle is not None
            self._end(lambda: handle.succeed(text="Goal reached."))

    def _start_planning_keep_patience(self) -> None:
        self.state = _State.PLANNING
        self.planning_since = self.node.now_ns()

    def _note_progress(self, pose: Floats, now: int) -> None:
        """Each cycle, as move_base: once the robot is ``oscillation_distance`` from where the
        oscillation clock last started, the clock starts again there (and, if oscillation
        caused the last recovery, the recoveries start over)."""
        if self.oscillation_pose is not None and (
            math.hypot(*(pose[:2] - self.oscillation_pose[:2])) < self.params.oscillation_distance
        ):
            return
        self.oscillation_pose = pose.copy()
        self.oscillation_since = now
        if self.recovery_trigger is _Trigger.OSCILLATION:
            self.recovery_index = 0

    # --- recoveries ----------------------------------------------------------------------------
    def _behaviours(self) -> list[tuple[str, ClearCostmapParams | RotateRecoveryParams]]:
        return self.recoveries if self.params.recovery_behavior_enabled else []

    def _recover(self, why: str, trigger: _Trigger) -> None:
        """The next recovery behaviour (after a recovery the oscillation clock restarts but
        not where it counts from), or abort when all have run."""
        self.recovery_trigger = trigger
        behaviours = self._behaviours()
        if self.recovery_index >= len(behaviours):
            handle = self.handle
            assert handle is not None
            after = " even after executing recovery behaviors" if behaviours else ""
            self._end(lambda: handle.abort(text=f"Aborting: {why}{after}."))
            return
        name, clearing = behaviours[self.recovery_index]
        self.recovery_index += 1
        logger.info("%s: %s; recovery: %s", self.node.full_name, why, name)
        if isinstance(clearing, RotateRecoveryParams):
            self.state = _State.CLEARING
            self.rotation = None
            self.rotating = name
            return
        for which, costmap in (("global", self.global_costmap), ("local", self.local_costmap)):
            if not clearing.affects(which):
                continue
            costmap.clear_area(
                clearing.reset_distance,
                clearing.layer_names,
                invert=clearing.invert_area_to_clear,
            )
            if clearing.force_updating:
                costmap.update_now()
        self._start_planning()

    def _clearing_step(self, now: int) -> None:
        """rotate_recovery: one turn in place (run at the controller's cycle), ended early
        when the rest of the turn would put the footprint in an obstacle."""
        del now
        pose = self.local_costmap.robot_pose()
        if pose is None:
            self._stop()
            return
        here = (float(pose[0]), float(pose[1]), float(pose[2]))
        if self.rotation is None:
            params = dict(self.recoveries)[self.rotating]
            assert isinstance(params, RotateRecoveryParams)
            self.rotation = RotateRecovery(params, here[2])
        step = self.rotation.step(self.local_costmap.grid(), here, self.local_costmap.footprint())
        if step.outcome is not RotateOutcome.ROTATING:
            if step.outcome is RotateOutcome.BLOCKED:
                logger.info("%s: rotate_recovery stopped: the turn is blocked", self.node.full_name)
            self._stop()
            self.rotation = None
            self._start_planning()
            return
        self._send(0.0, 0.0, step.vth)

    # --- outputs -------------------------------------------------------------------------------
    def _send(self, vx: float, vy: float, vth: float) -> None:
        self.cmd_pub.publish_data(
            {"linear": {"x": vx, "y": vy, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": vth}}
        )

    def _stop(self) -> None:
        self._send(0.0, 0.0, 0.0)

    def _end(self, finish: Any) -> None:
        self.handle = None
        self.goal = None
        self.plan = None
        if self.params.shutdown_costmaps:
            self.global_costmap.stop()
            self.local_costmap.stop()
        finish()

    def _publish_goal(self) -> None:
        assert self.goal is not None
        path = self._path(self.goal[None, :], self.global_costmap.global_frame)
        self.goal_pub.publish(path.poses[0])

    def _publish_path(self, publisher: Any, poses: Floats, frame: str) -> None:
        publisher.publish(self._path(poses, frame))

    def _path(self, poses: Floats, frame: str) -> Any:
        """(N, 3) poses as a ``nav_msgs/Path`` stamped now."""
        header = build.header(self.node.now_ns(), frame)
        pose_stamped = types().cls("geometry_msgs/PoseStamped")
        stamped = [
            pose_stamped(header, message_from_data("geometry_msgs/Pose", _pose_data(x, y, yaw)))
            for x, y, yaw in np.asarray(poses, dtype=np.float64).reshape(-1, 3)
        ]
        return types().cls("nav_msgs/Path")(header, stamped)

    # --- services ------------------------------------------------------------------------------
    def _on_make_plan(self, request: Any) -> Any:
        response = types().cls("nav_msgs/srv/GetPlan_Response")
        goal = self._in_global_frame(request.goal)
        start_frame = request.start.header.frame_id
        start = (
            self._in_global_frame(request.start)
            if start_frame
            else self.global_costmap.robot_pose()
        )
        frame = self.global_costmap.global_frame
        empty = self._path(np.zeros((0, 3)), frame)
        if goal is None or start is None:
            return response(empty)
        self.global_costmap.update_now()
        try:
            plan = self.global_planner.plan(self.global_costmap.grid(), start, goal)
        except NoPathError:
            return response(empty)
        return response(self._path(plan, frame))

    def _on_clear_costmaps(self, request: Any) -> Any:
        del request
        self.global_costmap.reset()
        self.local_costmap.reset()
        return types().cls("std_srvs/srv/Empty_Response")()


EXECUTABLES: dict[str, Starter] = {
    "move_base": stopping_on_bad_values(lambda session, spec, node: _MoveBase(node, session, spec))
}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
