"""actionlib's SimpleActionServer: one goal at a time. A new goal preempts the current one
(whose code sees :meth:`SimpleActionServer.is_preempt_requested`) and replaces any goal still
waiting; with an ``execute_cb`` each accepted goal runs in a thread of the server's own."""

from __future__ import annotations

import threading
import traceback
from collections.abc import Callable
from typing import Any

from belvedere.ros1 import rospy
from belvedere.ros1.actionlib._server import ActionServer, ServerGoalHandle
from belvedere.ros1.actionlib._spec import action_types
from belvedere.ros1.actionlib._states import GoalStatus

__all__ = ["SimpleActionServer"]

_REPLACED = "This goal was canceled because another goal was received by the simple action server"


class SimpleActionServer:
    """Serves the action ``name`` of ``ActionSpec``; ``execute_cb(goal)`` runs each goal to
    its end (with :meth:`set_succeeded`, :meth:`set_aborted` or :meth:`set_preempted`).
    Without one, register a goal callback and call :meth:`accept_new_goal`."""

    def __init__(
        self,
        name: str,
        ActionSpec: Any,  # noqa: N803 (actionlib's name)
        execute_cb: Callable[[Any], object] | None = None,
        auto_start: bool = True,
    ) -> None:
        action_types(ActionSpec)  # a bad spec fails here, before the execute thread starts
        self.new_goal = False
        self.preempt_request = False
        self.new_goal_preempt_request = False
        self.execute_callback = execute_cb
        self.goal_callback: Callable[[], object] | None = None
        self.preempt_callback: Callable[[], object] | None = None
        self.need_to_terminate = False
        self.terminate_mutex = threading.RLock()
        # The server calls in holding its own lock: take this one only after that one.
        self.lock = threading.RLock()
        self.execute_condition = threading.Condition(self.lock)
        self.current_goal = ServerGoalHandle()
        self.next_goal = ServerGoalHandle()
        self.execute_thread: threading.Thread | None = None
        if execute_cb is not None:
            # A daemon: a script that ends without shutting down must not hang on it.
            self.execute_thread = threading.Thread(
                target=self.executeLoop, name="SimpleActionServer", daemon=True
            )
            self.execute_thread.start()
        self.action_server = ActionServer(
            name,
            ActionSpec,
            self.internal_goal_callback,
            self.internal_preempt_callback,
            auto_start,
        )

    def __del__(self) -> None:
        if getattr(self, "execute_thread", None) is not None:
            with self.terminate_mutex:
                self.need_to_terminate = True

    # --- for the user's code ---------------------------------------------------------------------
    def accept_new_goal(self) -> Any:
        """Make the waiting goal the current one (preempting the current goal) and return its
        ``*Goal`` message; None (and an error) when no goal waits."""
        with self.action_server.lock, self.lock:
            if not self.new_goal or not self.next_goal.get_goal():
                rospy.logerr("Attempting to accept the next goal when a new goal is not available")
                return None
            if (
                self.is_active()
                and self.current_goal.get_goal()
                and self.current_goal != self.next_goal
            ):
                self.current_goal.set_canceled(None, _REPLACED)
            rospy.logdebug("Accepting a new goal")
            self.current_goal = self.next_goal
            self.new_goal = False
            self.preempt_request = self.new_goal_preempt_request
            self.new_goal_preempt_request = False
            self.current_goal.set_accepted(
                "This goal has been accepted by the simple action server"
            )
            return self.current_goal.get_goal()

    def is_new_goal_available(self) -> bool:
        return self.new_goal

    def is_preempt_requested(self) -> bool:
        """Whether the current goal was canceled or a newer goal came."""
        return self.preempt_request

    def is_active(self) -> bool:
        """Whether the current goal is ACTIVE or PREEMPTING."""
        if not self.current_goal.get_goal():
            return False
        status = self.current_goal.get_goal_status().status
        return bool(status in (GoalStatus.ACTIVE, GoalStatus.PREEMPTING))

    def set_succeeded(self, result: Any = None, text: str = "") -> None:
        with self.action_server.lock, self.lock:
            self.current_goal.set_succeeded(result or self.get_default_result(), text)

    def set_aborted(self, result: Any = None, text: str = "") -> None:
        with self.action_server.lock, self.lock:
            self.current_goal.set_aborted(result or self.get_default_result(), text)

    def set_preempted(self, result: Any = None, text: str = "") -> None:
        with self.action_server.lock, self.lock:
            rospy.logdebug("Setting the current goal as canceled")
            self.current_goal.set_canceled(result or self.get_default_result(), text)

    def publish_feedback(self, feedback: Any) -> None:
        self.current_goal.publish_feedback(feedback)

    def get_default_result(self) -> Any:
        return self.action_server.ActionResultType()

    def register_goal_callback(self, cb: Callable[[], object]) -> None:
        """``cb()`` is called when a new goal waits (not with an ``execute_cb``)."""
        if self.execute_callback:
            rospy.logwarn(
                "Cannot call SimpleActionServer.register_goal_callback() because an "
                "executeCallback exists. Not going to register it."
            )
        else:
            self.goal_callback = cb

    def register_preempt_callback(self, cb: Callable[[], object]) -> None:
        """``cb()`` is called when the current goal is asked to stop."""
        self.preempt_callback = cb

    def start(self) -> None:
        self.action_server.start()

    # --- from the action server ------------------------------------------------------------------
    def internal_goal_callback(self, goal: ServerGoalHandle) -> None:
        try:
            self._take_goal(goal)
        except Exception as ex:  # noqa: BLE001 (a user callback failed: log it, as actionlib)
            rospy.logerr("SimpleActionServer.internal_goal_callback - exception %s", str(ex))

    def _take_goal(self, goal: ServerGoalHandle) -> None:
        with self.execute_condition:
            rospy.logdebug(
                "A new goal %s has been received by the single goal action server",
                goal.get_goal_id().id,
            )
            stamp = goal.get_goal_id().stamp
            current, waiting = self.current_goal, self.next_goal
            newest = (not current.get_goal() or stamp >= current.get_goal_id().stamp) and (
                not waiting.get_goal() or stamp >= waiting.get_goal_id().stamp
            )
            if not newest:  # a newer goal came first: this one never runs
                goal.set_canceled(None, _REPLACED)
                return
            if waiting.get_goal() and (not current.get_goal() or waiting != current):
                waiting.set_canceled(None, _REPLACED)
            self.next_goal = goal
            self.new_goal = True
            self.new_goal_preempt_request = False
            if self.is_active():
                self.preempt_request = True
                if self.preempt_callback:
                    self.preempt_callback()
            if self.goal_callback:
                self.goal_callback()
            self.execute_condition.notify()

    def internal_preempt_callback(self, preempt: ServerGoalHandle) -> None:
        with self.lock:
            rospy.logdebug("A preempt has been received by the SimpleActionServer")
            if preempt == self.current_goal:
                rospy.logdebug(
                    "Setting preempt_request bit for the current goal to TRUE and invoking callback"
                )
                self.preempt_request = True
                if self.preempt_callback:
                    self.preempt_callback()
            elif preempt == self.next_goal:
                rospy.logdebug("Setting preempt request bit for the next goal to TRUE")
                self.new_goal_preempt_request = True

    def executeLoop(self) -> None:  # noqa: N802 (actionlib's name)
        """The execute thread: runs ``execute_cb`` on each goal accepted, one at a time."""
        while not rospy.is_shutdown():
            with self.terminate_mutex:
                if self.need_to_terminate:
                    break
            if self.is_active():
                rospy.logerr("Should never reach this code with an active goal")
                return
            if self.is_new_goal_available():
                goal = self.accept_new_goal()
                if self.execute_callback is None:
                    rospy.logerr(
                        "execute_callback_ must exist. This is a bug in SimpleActionServer"
                    )
                    return
                self._execute(goal)
            with self.execute_condition:
                self.execute_condition.wait(0.1)

    def _execute(self, goal: Any) -> None:
        assert self.execute_callback is not None
        try:
            self.execute_callback(goal)
            if self.is_active():
                rospy.logwarn(
                    "Your executeCallback did not set the goal to a terminal status.  "
                    "This is a bug in your ActionServer implementation. Fix your code!  "
                    "For now, the ActionServer will set this goal to aborted"
                )
                self.set_aborted(None, "No terminal state was set.")
        except Exception as ex:  # noqa: BLE001 (the user's code failed: the goal aborts)
            rospy.logerr(
                "Exception in your execute callback: %s\n%s", str(ex), traceback.format_exc()
            )
            self.set_aborted(None, f"Exception in execute callback: {ex}")
