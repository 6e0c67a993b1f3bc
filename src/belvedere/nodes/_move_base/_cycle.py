"""move_base's control cycle: planning, controlling and clearing, with its patience,
oscillation and recovery rules."""

from __future__ import annotations

import logging
import math
from enum import Enum
from typing import TYPE_CHECKING, Any

from belvedere.graph import NS, Publisher
from belvedere.nav.local import Command, NoTrajectoryError, TrajectoryPlannerROS
from belvedere.nav.planners import NoPathError
from belvedere.nav.recovery import (
    ClearCostmapParams,
    RotateOutcome,
    RotateRecovery,
    RotateRecoveryParams,
)
from belvedere.nodes._move_base._io import Floats, NodeIO, _pose_data, _transform

__all__ = ["Cycle", "State", "Trigger"]

logger = logging.getLogger("belvedere.nodes.move_base")


class State(Enum):
    PLANNING = "planning"
    CONTROLLING = "controlling"
    CLEARING = "clearing"


class Trigger(Enum):
    """What sent move_base to its recoveries last; only progress of that kind (a plan, a
    command, or moving ``oscillation_distance``) starts the recoveries over."""

    PLANNING = "planning"
    CONTROLLING = "controlling"
    OSCILLATION = "oscillation"


class Cycle(NodeIO):
    """The node's control cycle and recoveries (a base of the node, over its state)."""

    if TYPE_CHECKING:
        local_planner: Any
        plan_pub: Publisher
        local_plan_pub: Publisher
        followed_pub: Publisher
        velocity: Floats
        state: State
        plan_to_local: tuple[float, float, float] | None
        recovery_index: int
        recovery_trigger: Trigger
        planning_since: int
        last_valid_control: int
        last_plan_at: int
        retries: int
        oscillation_pose: Floats | None
        oscillation_since: int
        rotation: RotateRecovery | None
        rotating: str
        recoveries: list[tuple[str, ClearCostmapParams | RotateRecoveryParams]]

    # --- the cycle ---------------------------------------------------------------------------
    def _start_planning(self) -> None:
        self.state = State.PLANNING
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
        if self.state is State.PLANNING:
            self._plan_step(now)
        elif self.state is State.CONTROLLING:
            self._control_step(now)
        else:
            self._clearing_step(now)

    def _plan_step(self, now: int) -> None:
        if self._make_plan():
            self.state = State.CONTROLLING
            self.last_valid_control = now
            if self.recovery_trigger is Trigger.PLANNING:
                self.recovery_index = 0
            return
        self.retries += 1
        p = self.params
        out_of_patience = now - self.planning_since > round(p.planner_patience * NS)
        out_of_retries = 0 <= p.max_planning_retries < self.retries
        if out_of_patience or out_of_retries:
            self._stop()
            self._recover("failed to find a valid plan", Trigger.PLANNING)

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
            self._recover("the robot is oscillating", Trigger.OSCILLATION)
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
                    f"the local planner found no valid command ({err})", Trigger.CONTROLLING
                )
            else:
                self._start_planning_keep_patience()
            return
        self.last_valid_control = now
        if self.recovery_trigger is Trigger.CONTROLLING:
            self.recovery_index = 0
        self._send(command.vx, command.vy, command.vth)
        self._publish_path(self.local_plan_pub, command.local_plan, self.local_costmap.global_frame)
        if self.local_planner.goal_reached(pose, self.velocity):
            self._stop()
            handle = self.handle
            assert handle is not None
            self._end(lambda: handle.succeed(text="Goal reached."))

    def _start_planning_keep_patience(self) -> None:
        self.state = State.PLANNING
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
        if self.recovery_trigger is Trigger.OSCILLATION:
            self.recovery_index = 0

    # --- recoveries ----------------------------------------------------------------------------
    def _behaviours(self) -> list[tuple[str, ClearCostmapParams | RotateRecoveryParams]]:
        return self.recoveries if self.params.recovery_behavior_enabled else []

    def _recover(self, why: str, trigger: Trigger) -> None:
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
            self.state = State.CLEARING
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
