"""actionlib's ActionServer: takes goals on ``<ns>/goal`` and cancels on ``<ns>/cancel``,
publishes every goal's status on ``<ns>/status`` (latched, and again at
``actionlib_status_frequency``, 5 Hz by default), results on ``<ns>/result`` and feedback on
``<ns>/feedback``, as ROS 1's actionlib does on the wire.

Each goal has a status tracker; :class:`ServerGoalHandle` moves it through the server's states:
PENDING → ACTIVE (accepted) → SUCCEEDED / ABORTED / PREEMPTED, PENDING → REJECTED or RECALLED,
with RECALLING and PREEMPTING while a cancel request waits on the user's code. A finished goal
stays in the status list ``status_list_timeout`` seconds (5) after it ended.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from belvedere.ros1 import rospy
from belvedere.ros1.actionlib._ids import GoalIDGenerator
from belvedere.ros1.actionlib._spec import action_types
from belvedere.ros1.actionlib._states import GoalID, GoalStatus, GoalStatusArray

__all__ = ["ActionServer", "ServerGoalHandle", "StatusTracker", "nop_cb"]

GoalCallback = Callable[["ServerGoalHandle"], object]


def nop_cb(goal_handle: ServerGoalHandle) -> None:
    """A callback that does nothing (the default cancel callback)."""


class StatusTracker:
    """The server's record of one goal: the goal message, its ``GoalStatus``, and when the
    record may leave the status list."""

    def __init__(self, goal_id: Any = None, status: int | None = None, goal: Any = None) -> None:
        self.goal: Any = None
        self.status: Any = GoalStatus()
        self.handle_destruction_time: Any = rospy.Time()
        self.has_handles = False
        """A goal that came has handles; one known only from a cancel request has none."""
        if goal_id:  # a cancel request for a goal not seen yet
            self.status.goal_id = goal_id
            self.status.status = status
            return
        self.goal = goal
        self.has_handles = True
        self.status.goal_id = goal.goal_id
        self.status.status = GoalStatus.PENDING
        if self.status.goal_id.id == "":
            self.status.goal_id = GoalIDGenerator().generate_ID()
        if self.status.goal_id.stamp == rospy.Time():
            self.status.goal_id.stamp = rospy.Time.now()


class ServerGoalHandle:
    """The server's handle on one goal: its message, its id, and the calls that move it on.

    A call that does not fit the goal's status is logged as an error and changes nothing."""

    def __init__(
        self,
        status_tracker: StatusTracker | None = None,
        action_server: ActionServer | None = None,
        handle_tracker: object = None,
    ) -> None:
        self.status_tracker = status_tracker
        self.action_server = action_server
        self.handle_tracker = handle_tracker
        self.goal: Any = status_tracker.goal if status_tracker else None

    # --- accessors -------------------------------------------------------------------------------
    def get_goal(self) -> Any:
        """The ``*Goal`` message (None for an empty handle)."""
        return self.goal.goal if self.goal else None

    def get_goal_id(self) -> Any:
        if not self._bound():
            rospy.logerr("Attempt to get a goal id on an uninitialized ServerGoalHandle")
            return GoalID()
        with self._server.lock:
            return self._tracker.status.goal_id

    def get_goal_status(self) -> Any:
        if not self._bound():
            rospy.logerr("Attempt to get goal status on an uninitialized ServerGoalHandle")
            return GoalStatus()
        with self._server.lock:
            return self._tracker.status

    def get_default_result(self) -> Any:
        return self._server.ActionResultType()

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ServerGoalHandle) or not self.goal or not other.goal:
            return False
        return bool(self.get_goal_id().id == other.get_goal_id().id)

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return hash(self.get_goal_id().id)

    # --- transitions -----------------------------------------------------------------------------
    def set_accepted(self, text: str = "") -> None:
        """PENDING → ACTIVE (RECALLING → PREEMPTING: a cancel came meanwhile)."""
        self._debug("Accepting goal")
        if not self._bound():
            return
        with self._server.lock:
            status = self._tracker.status.status
            if status == GoalStatus.PENDING:
                self._move(GoalStatus.ACTIVE, text)
            elif status == GoalStatus.RECALLING:
                self._move(GoalStatus.PREEMPTING, text)
            else:
                rospy.logerr(
                    "To transition to an active state, the goal must be in a pending or "
                    "recalling state, it is currently in state: %d",
                    status,
                )

    def set_canceled(self, result: Any = None, text: str = "") -> None:
        """End as RECALLED (not started) or PREEMPTED (started)."""
        self._debug("Setting status to canceled on goal")
        if not self._bound():
            return
        with self._server.lock:
            status = self._tracker.status.status
            if status in (GoalStatus.PENDING, GoalStatus.RECALLING):
                self._end(GoalStatus.RECALLED, result, text)
            elif status in (GoalStatus.ACTIVE, GoalStatus.PREEMPTING):
                self._end(GoalStatus.PREEMPTED, result, text)
            else:
                rospy.logerr(
                    "To transition to a cancelled state, the goal must be in a pending, "
                    "recalling, active, or preempting state, it is currently in state: %d",
                    status,
                )

    def set_rejected(self, result: Any = None, text: str = "") -> None:
        """End a goal not started as REJECTED."""
        self._debug("Setting status to rejected on goal")
        if not self._bound():
            return
        with self._server.lock:
            status = self._tracker.status.status
            if status in (GoalStatus.PENDING, GoalStatus.RECALLING):
                self._end(GoalStatus.REJECTED, result, text)
            else:
                rospy.logerr(
                    "To transition to a rejected state, the goal must be in a pending or "
                    "recalling state, it is currently in state: %d",
                    status,
                )

    def set_aborted(self, result: Any = None, text: str = "") -> None:
        """End a started goal as ABORTED."""
        self._finish(GoalStatus.ABORTED, "aborted", result, text)

    def set_succeeded(self, result: Any = None, text: str = "") -> None:
        """End a started goal as SUCCEEDED."""
        self._finish(GoalStatus.SUCCEEDED, "succeeded", result, text)

    def publish_feedback(self, feedback: Any) -> None:
        """Send ``feedback`` (a ``*Feedback`` message) to the goal's clients."""
        self._debug("Publishing feedback for goal")
        if not self.goal:
            rospy.logerr("Attempt to publish feedback on an uninitialized ServerGoalHandle")
            return
        with self._server.lock:
            self._server.publish_feedback(self._tracker.status, feedback)

    def set_cancel_requested(self) -> bool:
        """PENDING → RECALLING or ACTIVE → PREEMPTING; True when the user's cancel callback
        should hear of it."""
        self._debug("Transisitoning to a cancel requested state on goal")
        if not self.goal:
            return False
        with self._server.lock:
            status = self._tracker.status.status
            if status == GoalStatus.PENDING:
                self._tracker.status.status = GoalStatus.RECALLING
            elif status == GoalStatus.ACTIVE:
                self._tracker.status.status = GoalStatus.PREEMPTING
            else:
                return False
            self._server.publish_status()
            return True

    # --- internals -------------------------------------------------------------------------------
    @property
    def _server(self) -> ActionServer:
        assert self.action_server is not None
        return self.action_server

    @property
    def _tracker(self) -> StatusTracker:
        assert self.status_tracker is not None
        return self.status_tracker

    def _bound(self) -> bool:
        if self.goal:
            return True
        rospy.logerr("Attempt to set status on an uninitialized ServerGoalHandle")
        return False

    def _debug(self, what: str) -> None:
        if self.goal:
            goal_id = self._tracker.status.goal_id
            rospy.logdebug("%s, id: %s, stamp: %.2f", what, goal_id.id, goal_id.stamp.to_sec())

    def _move(self, status: int, text: str) -> None:
        self._tracker.status.status = status
        self._tracker.status.text = text
        self._server.publish_status()

    def _end(self, status: int, result: Any, text: str) -> None:
        tracker = self._tracker
        tracker.status.status = status
        tracker.status.text = text
        tracker.handle_destruction_time = rospy.Time.now()
        self._server.publish_result(tracker.status, result or self.get_default_result())

    def _finish(self, status: int, word: str, result: Any, text: str) -> None:
        self._debug(f"Setting status to {word} on goal")
        if not self._bound():
            return
        with self._server.lock:
            now = self._tracker.status.status
            if now in (GoalStatus.PREEMPTING, GoalStatus.ACTIVE):
                self._end(status, result, text)
            else:
                rospy.logerr(
                    f"To transition to a {word} state, the goal must be in a preempting or "
                    "active state, it is currently in state: %d",
                    now,
                )


class ActionServer:
    """Serves the action ``ns`` of ``ActionSpec`` (a ``*Action`` message class):
    ``goal_cb(handle)`` for each new goal, ``cancel_cb(handle)`` for each cancel request.
    Start it with :meth:`start` (``auto_start=False``, as actionlib advises)."""

    def __init__(
        self,
        ns: str,
        ActionSpec: Any,  # noqa: N803 (actionlib's name)
        goal_cb: GoalCallback,
        cancel_cb: GoalCallback = nop_cb,
        auto_start: bool = True,
    ) -> None:
        self.ns = ns
        wire = action_types(ActionSpec)
        self.ActionSpec = ActionSpec
        self.ActionGoal = wire.goal
        self.ActionResult = wire.result
        self.ActionResultType = wire.result_body
        self.ActionFeedback = wire.feedback
        self.goal_sub: Any = None
        self.cancel_sub: Any = None
        self.status_pub: Any = None
        self.result_pub: Any = None
        self.feedback_pub: Any = None
        self.status_timer: Any = None
        self.lock = threading.RLock()
        self.status_list: list[StatusTracker] = []
        self.last_cancel: Any = rospy.Time()
        self.status_list_timeout: Any = rospy.Duration()
        self.status_frequency = 5.0
        self.id_generator = GoalIDGenerator()
        self.goal_callback = goal_cb
        self.cancel_callback = cancel_cb
        self.auto_start = auto_start
        self.started = False
        if auto_start:
            rospy.logwarn(
                "You've passed in true for auto_start to the python action server, you should "
                "always pass in false to avoid race conditions."
            )
            self.start()

    def register_goal_callback(self, cb: GoalCallback) -> None:
        self.goal_callback = cb

    def register_cancel_callback(self, cancel_cb: GoalCallback) -> None:
        self.cancel_callback = cancel_cb

    def start(self) -> None:
        """Join the action's topics and publish the status list."""
        with self.lock:
            self.initialize()
            self.started = True
            self.publish_status()

    def stop(self) -> None:
        """Leave the action's topics (goals being worked on are left as they are)."""
        with self.lock:
            self.started = False
            if self.status_timer is not None:
                self.status_timer.shutdown()
            for endpoint in (
                self.goal_sub,
                self.cancel_sub,
                self.status_pub,
                self.feedback_pub,
                self.result_pub,
            ):
                if endpoint is not None:
                    endpoint.unregister()

    def initialize(self) -> None:
        base = rospy.remap_name(self.ns)
        pub_size = rospy.get_param("actionlib_server_pub_queue_size", 50)
        self.pub_queue_size = pub_size if isinstance(pub_size, int) and pub_size >= 0 else 50
        sub_size = rospy.get_param("actionlib_server_sub_queue_size", -1)
        self.sub_queue_size = sub_size if isinstance(sub_size, int) and sub_size >= 0 else None
        self.status_pub = rospy.Publisher(
            base + "/status", GoalStatusArray, latch=True, queue_size=self.pub_queue_size
        )
        self.result_pub = rospy.Publisher(
            base + "/result", self.ActionResult, queue_size=self.pub_queue_size
        )
        self.feedback_pub = rospy.Publisher(
            base + "/feedback", self.ActionFeedback, queue_size=self.pub_queue_size
        )
        self.goal_sub = rospy.Subscriber(
            base + "/goal",
            self.ActionGoal,
            callback=self.internal_goal_callback,
            queue_size=self.sub_queue_size,
        )
        self.cancel_sub = rospy.Subscriber(
            base + "/cancel",
            GoalID,
            callback=self.internal_cancel_callback,
            queue_size=self.sub_queue_size,
        )
        self.status_frequency = self._status_frequency(base)
        timeout = rospy.get_param(base + "/status_list_timeout", 5.0)
        self.status_list_timeout = rospy.Duration(timeout)
        if self.status_frequency > 0.0:
            self.status_timer = rospy.Timer(
                rospy.Duration(1.0 / self.status_frequency), self.publish_status_async
            )

    @staticmethod
    def _status_frequency(base: str) -> float:
        old_name = base + "/status_frequency"
        if rospy.has_param(old_name):
            value = rospy.get_param(old_name, 5.0)
            rospy.logwarn(
                "You're using the deprecated status_frequency parameter, please switch to "
                "actionlib_status_frequency."
            )
            return float(value)
        found = rospy.search_param("actionlib_status_frequency")
        return 5.0 if found is None else float(rospy.get_param(found, 5.0))

    # --- outgoing --------------------------------------------------------------------------------
    def publish_result(self, status: Any, result: Any) -> None:
        with self.lock:
            ar = self.ActionResult(status=status, result=result)
            ar.header.stamp = rospy.Time.now()
            if not rospy.is_shutdown():
                self.result_pub.publish(ar)
            self.publish_status()

    def publish_feedback(self, status: Any, feedback: Any) -> None:
        with self.lock:
            af = self.ActionFeedback(status=status, feedback=feedback)
            af.header.stamp = rospy.Time.now()
            if not rospy.is_shutdown():
                self.feedback_pub.publish(af)

    def publish_status_async(self, event: Any = None) -> None:
        with self.lock:
            if self.started:
                self.publish_status()

    def publish_status(self) -> None:
        """Publish every goal's status, first dropping those ended long enough ago."""
        with self.lock:
            now = rospy.Time.now()
            kept = []
            for tracker in self.status_list:
                ended = tracker.handle_destruction_time
                if ended != rospy.Time() and ended + self.status_list_timeout < now:
                    rospy.logdebug(
                        "Item %s with destruction time of %.3f being removed from list.  "
                        "Now = %.3f",
                        tracker.status.goal_id,
                        ended.to_sec(),
                        now.to_sec(),
                    )
                    continue
                kept.append(tracker)
            self.status_list = kept
            array = GoalStatusArray(status_list=[t.status for t in kept])
            array.header.stamp = rospy.Time.now()
            if not rospy.is_shutdown():
                self.status_pub.publish(array)

    # --- incoming --------------------------------------------------------------------------------
    def internal_cancel_callback(self, goal_id: Any) -> None:
        with self.lock:
            if not self.started:
                return
            rospy.logdebug("The action server has received a new cancel request")
            zero = rospy.Time()
            everything = goal_id.id == "" and goal_id.stamp == zero
            found = False
            for tracker in list(self.status_list):
                this_one = goal_id.id == tracker.status.goal_id.id
                before = goal_id.stamp != zero and tracker.status.goal_id.stamp <= goal_id.stamp
                if not (everything or this_one or before):
                    continue
                found = found or this_one
                if not tracker.has_handles:
                    tracker.has_handles = True
                    tracker.handle_destruction_time = rospy.Time.now()
                handle = ServerGoalHandle(tracker, self, tracker)
                if handle.set_cancel_requested():
                    self.cancel_callback(handle)
            if goal_id.id != "" and not found:
                # the goal may still come: remember it is canceled
                tracker = StatusTracker(goal_id, GoalStatus.RECALLING)
                tracker.handle_destruction_time = rospy.Time.now()
                self.status_list.append(tracker)
            if goal_id.stamp > self.last_cancel:
                self.last_cancel = goal_id.stamp

    def internal_goal_callback(self, goal: Any) -> None:
        with self.lock:
            if not self.started:
                return
            rospy.logdebug("The action server has received a new goal request")
            for tracker in self.status_list:
                if goal.goal_id.id != tracker.status.goal_id.id:
                    continue
                rospy.logdebug(
                    "Goal %s was already in the status list with status %i",
                    goal.goal_id.id,
                    tracker.status.status,
                )
                if tracker.status.status == GoalStatus.RECALLING:  # canceled before it came
                    tracker.status.status = GoalStatus.RECALLED
                    self.publish_result(tracker.status, self.ActionResultType())
                if not tracker.has_handles:
                    tracker.handle_destruction_time = rospy.Time.now()
                return
            tracker = StatusTracker(None, None, goal)
            self.status_list.append(tracker)
            handle = ServerGoalHandle(tracker, self, tracker)
            stamp = goal.goal_id.stamp
            if stamp != rospy.Time() and stamp <= self.last_cancel:
                handle.set_canceled(
                    None,
                    "This goal handle was canceled by the action server because its timestamp "
                    "is before the timestamp of the last cancel request",
                )
            else:
                self.goal_callback(handle)
