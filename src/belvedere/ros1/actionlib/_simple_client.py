"""actionlib's SimpleActionClient: one goal at a time, seen as PENDING, ACTIVE or DONE, with
callbacks for the start, the feedback and the end of the goal."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from belvedere.ros1 import rospy
from belvedere.ros1.actionlib._client import ActionClient, ClientGoalHandle
from belvedere.ros1.actionlib._states import CommState, GoalStatus, SimpleGoalState

__all__ = ["SimpleActionClient"]

DoneCallback = Callable[[int, Any], object]
ActiveCallback = Callable[[], object]
FeedbackCallback = Callable[[Any], object]


class SimpleActionClient:
    """A client of the action server at ``ns`` that follows the last goal it sent."""

    def __init__(self, ns: str, ActionSpec: Any) -> None:  # noqa: N803 (actionlib's name)
        self.action_client = ActionClient(ns, ActionSpec)
        self.simple_state = SimpleGoalState.DONE
        self.gh: ClientGoalHandle | None = None
        self.done_condition = threading.Condition()
        # Held while a goal is sent and while its callbacks run. actionlib takes no lock: a
        # server quick to answer can then call back before the new goal is followed, and the
        # goal's start (active_cb) is lost with a "not tracking" error.
        self._following = threading.RLock()
        self.done_cb: DoneCallback | None = None
        self.active_cb: ActiveCallback | None = None
        self.feedback_cb: FeedbackCallback | None = None

    def wait_for_server(self, timeout: Any = None) -> bool:
        """True once the server is connected, False after ``timeout`` (a Duration in ROS time;
        zero, the default, waits forever)."""
        return self.action_client.wait_for_server(timeout)

    def send_goal(
        self,
        goal: Any,
        done_cb: DoneCallback | None = None,
        active_cb: ActiveCallback | None = None,
        feedback_cb: FeedbackCallback | None = None,
    ) -> None:
        """Send ``goal`` and follow it instead of any earlier goal (which is not canceled).

        ``done_cb(state, result)`` is called when it ends, ``active_cb()`` when the server
        starts it, ``feedback_cb(feedback)`` on each feedback."""
        with self._following:
            self.stop_tracking_goal()
            self.done_cb = done_cb
            self.active_cb = active_cb
            self.feedback_cb = feedback_cb
            self.simple_state = SimpleGoalState.PENDING
            self.gh = self.action_client.send_goal(
                goal, self._handle_transition, self._handle_feedback
            )

    def send_goal_and_wait(
        self, goal: Any, execute_timeout: Any = None, preempt_timeout: Any = None
    ) -> int:
        """Send ``goal`` and wait for its end; past ``execute_timeout`` cancel it and wait up to
        ``preempt_timeout`` more. Returns its state (zero timeouts wait forever)."""
        if execute_timeout is None:
            execute_timeout = rospy.Duration()
        if preempt_timeout is None:
            preempt_timeout = rospy.Duration()
        self.send_goal(goal)
        if not self.wait_for_result(execute_timeout):
            rospy.logdebug("Canceling goal")
            self.cancel_goal()
            if self.wait_for_result(preempt_timeout):
                rospy.logdebug(
                    "Preempt finished within specified preempt_timeout [%.2f]",
                    preempt_timeout.to_sec(),
                )
            else:
                rospy.logdebug(
                    "Preempt didn't finish specified preempt_timeout [%.2f]",
                    preempt_timeout.to_sec(),
                )
        return self.get_state()

    def wait_for_result(self, timeout: Any = None) -> bool:
        """True once the goal is done, False after ``timeout`` (a Duration in ROS time; zero,
        the default, waits forever) or at shutdown."""
        if not self.gh:
            rospy.logerr("Called wait_for_result when no goal exists")
            return False
        if timeout is None:
            timeout = rospy.Duration()
        zero = rospy.Duration()
        deadline = rospy.get_rostime() + timeout
        # Wake at least every 0.1 s: ROS time may jump (simulated time) without a notify.
        period = rospy.Duration(0.1)
        with self.done_condition:
            while not rospy.is_shutdown():
                left = deadline - rospy.get_rostime()
                if timeout > zero and left <= zero:
                    break
                if self.simple_state == SimpleGoalState.DONE:
                    break
                if left > period or timeout == zero:
                    left = period
                self.done_condition.wait(left.to_sec())
        return self.simple_state == SimpleGoalState.DONE

    def get_result(self) -> Any:
        """The goal's ``*Result`` (None before it came, or with no goal)."""
        if not self.gh:
            rospy.logerr("Called get_result when no goal is running")
            return None
        return self.gh.get_result()

    def get_state(self) -> int:
        """The goal's status (``GoalStatus``); RECALLING reads as PENDING, PREEMPTING as
        ACTIVE, and LOST when no goal is followed."""
        if not self.gh:
            return int(GoalStatus.LOST)
        status = self.gh.get_goal_status()
        if status == GoalStatus.RECALLING:
            return int(GoalStatus.PENDING)
        if status == GoalStatus.PREEMPTING:
            return int(GoalStatus.ACTIVE)
        return status

    def get_goal_status_text(self) -> str:
        """The text the server gave with the goal's latest status."""
        if not self.gh:
            text = "Called get_goal_status_text when no goal is running"
            rospy.logerr(text)
            return f"ERROR: {text}"
        return self.gh.get_goal_status_text()

    def cancel_all_goals(self) -> None:
        self.action_client.cancel_all_goals()

    def cancel_goals_at_and_before_time(self, time: Any) -> None:
        self.action_client.cancel_goals_at_and_before_time(time)

    def cancel_goal(self) -> None:
        """Ask the server to cancel the goal followed."""
        if self.gh:
            self.gh.cancel()

    def stop_tracking_goal(self) -> None:
        """Forget the goal (its callbacks are no longer called); it is not canceled."""
        self.gh = None

    # --- from the goal's state machine -----------------------------------------------------------
    def _handle_transition(self, gh: ClientGoalHandle) -> None:
        with self._following:
            self._transition(gh)

    def _transition(self, gh: ClientGoalHandle) -> None:
        if gh != self.gh:
            rospy.logerr("Got a transition callback on a goal handle that we're not tracking")
            return
        comm_state = gh.get_comm_state()
        if comm_state in (CommState.ACTIVE, CommState.PREEMPTING):
            if self.simple_state == SimpleGoalState.PENDING:
                self.simple_state = SimpleGoalState.ACTIVE
                if self.active_cb:
                    self.active_cb()
            elif self.simple_state == SimpleGoalState.DONE:
                rospy.logerr(self._unexpected(comm_state))
        elif comm_state == CommState.RECALLING:
            if self.simple_state != SimpleGoalState.PENDING:
                rospy.logerr(self._unexpected(comm_state))
        elif comm_state == CommState.DONE:
            if self.simple_state == SimpleGoalState.DONE:
                rospy.logerr("SimpleActionClient received DONE twice")
                return
            if self.done_cb:
                self.done_cb(gh.get_goal_status(), gh.get_result())
            with self.done_condition:
                self.simple_state = SimpleGoalState.DONE
                self.done_condition.notify_all()

    def _unexpected(self, comm_state: int) -> str:
        return (
            f"Received comm state {CommState.to_string(comm_state)} when in simple state "
            f"{SimpleGoalState.to_string(self.simple_state)} with SimpleActionClient in NS "
            f"{rospy.resolve_name(self.action_client.ns)}"
        )

    def _handle_feedback(self, gh: ClientGoalHandle, feedback: Any) -> None:
        with self._following:
            self._feedback(gh, feedback)

    def _feedback(self, gh: ClientGoalHandle, feedback: Any) -> None:
        if not self.gh:
            return  # feedback of a goal just forgotten: not an error
        if gh != self.gh:
            mine = self.gh.comm_state_machine
            theirs = gh.comm_state_machine
            rospy.logerr(
                "Got a feedback callback on a goal handle that we're not tracking. "
                f"{mine.goal_id if mine else None} vs {theirs.goal_id if theirs else None}"
            )
            return
        if self.feedback_cb:
            self.feedback_cb(feedback)
