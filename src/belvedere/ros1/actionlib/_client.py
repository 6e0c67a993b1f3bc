"""actionlib's ActionClient: sends goals on ``<ns>/goal``, cancels on ``<ns>/cancel``, and
follows each goal's communication state from ``<ns>/status``, ``<ns>/result`` and
``<ns>/feedback``, as ROS 1's actionlib does on the wire.

Each goal sent has a :class:`ClientGoalHandle` whose state machine moves on every status the
server reports for it. The table below is actionlib's: for each communication state and goal
status, the states passed through (each one calls the goal's transition callback), nothing
(no change) or an error (a status that cannot follow that state).
"""

from __future__ import annotations

import itertools
import threading
import time
import weakref
from collections.abc import Callable
from typing import Any, Final

from belvedere.ros1 import rospy
from belvedere.ros1.actionlib._spec import action_types
from belvedere.ros1.actionlib._states import CommState, GoalID, GoalStatus, GoalStatusArray

__all__ = ["ActionClient", "ClientGoalHandle", "CommStateMachine", "GoalManager"]

TransitionCallback = Callable[["ClientGoalHandle"], object]
FeedbackCallback = Callable[["ClientGoalHandle", Any], object]

_S = GoalStatus
_C = CommState
_INVALID: Final = None
_STAY: Final[tuple[int, ...]] = ()

# comm state -> goal status -> the comm states to pass through (_STAY: none; _INVALID: error)
_TRANSITIONS: Final[dict[int, dict[int, tuple[int, ...] | None]]] = {
    _C.WAITING_FOR_GOAL_ACK: {
        _S.PENDING: (_C.PENDING,),
        _S.ACTIVE: (_C.ACTIVE,),
        _S.REJECTED: (_C.PENDING, _C.WAITING_FOR_RESULT),
        _S.RECALLING: (_C.PENDING, _C.RECALLING),
        _S.RECALLED: (_C.PENDING, _C.WAITING_FOR_RESULT),
        _S.PREEMPTED: (_C.ACTIVE, _C.PREEMPTING, _C.WAITING_FOR_RESULT),
        _S.SUCCEEDED: (_C.ACTIVE, _C.WAITING_FOR_RESULT),
        _S.ABORTED: (_C.ACTIVE, _C.WAITING_FOR_RESULT),
        _S.PREEMPTING: (_C.ACTIVE, _C.PREEMPTING),
    },
    _C.PENDING: {
        _S.PENDING: _STAY,
        _S.ACTIVE: (_C.ACTIVE,),
        _S.REJECTED: (_C.WAITING_FOR_RESULT,),
        _S.RECALLING: (_C.RECALLING,),
        _S.RECALLED: (_C.RECALLING, _C.WAITING_FOR_RESULT),
        _S.PREEMPTED: (_C.ACTIVE, _C.PREEMPTING, _C.WAITING_FOR_RESULT),
        _S.SUCCEEDED: (_C.ACTIVE, _C.WAITING_FOR_RESULT),
        _S.ABORTED: (_C.ACTIVE, _C.WAITING_FOR_RESULT),
        _S.PREEMPTING: (_C.ACTIVE, _C.PREEMPTING),
    },
    _C.ACTIVE: {
        _S.PENDING: _INVALID,
        _S.ACTIVE: _STAY,
        _S.REJECTED: _INVALID,
        _S.RECALLING: _INVALID,
        _S.RECALLED: _INVALID,
        _S.PREEMPTED: (_C.PREEMPTING, _C.WAITING_FOR_RESULT),
        _S.SUCCEEDED: (_C.WAITING_FOR_RESULT,),
        _S.ABORTED: (_C.WAITING_FOR_RESULT,),
        _S.PREEMPTING: (_C.PREEMPTING,),
    },
    _C.WAITING_FOR_RESULT: {
        _S.PENDING: _INVALID,
        _S.ACTIVE: _STAY,
        _S.REJECTED: _STAY,
        _S.RECALLING: _INVALID,
        _S.RECALLED: _STAY,
        _S.PREEMPTED: _STAY,
        _S.SUCCEEDED: _STAY,
        _S.ABORTED: _STAY,
        _S.PREEMPTING: _INVALID,
    },
    _C.WAITING_FOR_CANCEL_ACK: {
        _S.PENDING: _STAY,
        _S.ACTIVE: _STAY,
        _S.REJECTED: (_C.WAITING_FOR_RESULT,),
        _S.RECALLING: (_C.RECALLING,),
        _S.RECALLED: (_C.RECALLING, _C.WAITING_FOR_RESULT),
        _S.PREEMPTED: (_C.PREEMPTING, _C.WAITING_FOR_RESULT),
        _S.SUCCEEDED: (_C.PREEMPTING, _C.WAITING_FOR_RESULT),
        _S.ABORTED: (_C.PREEMPTING, _C.WAITING_FOR_RESULT),
        _S.PREEMPTING: (_C.PREEMPTING,),
    },
    _C.RECALLING: {
        _S.PENDING: _INVALID,
        _S.ACTIVE: _INVALID,
        _S.REJECTED: (_C.WAITING_FOR_RESULT,),
        _S.RECALLING: _STAY,
        _S.RECALLED: (_C.WAITING_FOR_RESULT,),
        _S.PREEMPTED: (_C.PREEMPTING, _C.WAITING_FOR_RESULT),
        _S.SUCCEEDED: (_C.PREEMPTING, _C.WAITING_FOR_RESULT),
        _S.ABORTED: (_C.PREEMPTING, _C.WAITING_FOR_RESULT),
        _S.PREEMPTING: (_C.PREEMPTING,),
    },
    _C.PREEMPTING: {
        _S.PENDING: _INVALID,
        _S.ACTIVE: _INVALID,
        _S.REJECTED: _INVALID,
        _S.RECALLING: _INVALID,
        _S.RECALLED: _INVALID,
        _S.PREEMPTED: (_C.WAITING_FOR_RESULT,),
        _S.SUCCEEDED: (_C.WAITING_FOR_RESULT,),
        _S.ABORTED: (_C.WAITING_FOR_RESULT,),
        _S.PREEMPTING: _STAY,
    },
    _C.DONE: {
        _S.PENDING: _INVALID,
        _S.ACTIVE: _INVALID,
        _S.REJECTED: _STAY,
        _S.RECALLING: _INVALID,
        _S.RECALLED: _STAY,
        _S.PREEMPTED: _STAY,
        _S.SUCCEEDED: _STAY,
        _S.ABORTED: _STAY,
        _S.PREEMPTING: _INVALID,
    },
}

_TERMINAL_STATUSES: Final = frozenset(
    {_S.PREEMPTED, _S.SUCCEEDED, _S.ABORTED, _S.REJECTED, _S.RECALLED, _S.LOST}
)
# States in which a goal the server no longer lists has been lost.
_EXPECT_LISTED: Final = frozenset(
    {
        _C.PENDING,
        _C.ACTIVE,
        _C.WAITING_FOR_CANCEL_ACK,
        _C.RECALLING,
        _C.PREEMPTING,
    }
)

_goal_numbers = itertools.count(1)
"""actionlib numbers goals per process, across all its clients."""
_goal_numbers_lock = threading.Lock()


class CommStateMachine:
    """One goal's exchange with the server: its state, its latest status and result."""

    def __init__(
        self,
        action_goal: Any,
        transition_cb: TransitionCallback | None,
        feedback_cb: FeedbackCallback | None,
        send_goal_fn: Callable[[Any], object],
        send_cancel_fn: Callable[[Any], object],
    ) -> None:
        self.action_goal = action_goal
        self.transition_cb = transition_cb
        self.feedback_cb = feedback_cb
        self.send_goal_fn = send_goal_fn
        self.send_cancel_fn = send_cancel_fn
        self.state = CommState.WAITING_FOR_GOAL_ACK
        self.mutex = threading.RLock()
        self.latest_goal_status: Any = GoalStatus(status=GoalStatus.PENDING)
        self.latest_result: Any = None

    @property
    def goal_id(self) -> str:
        return str(self.action_goal.goal_id.id)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, CommStateMachine) and self.goal_id == other.goal_id

    def __hash__(self) -> int:
        return hash(self.goal_id)

    def set_state(self, state: int) -> None:
        rospy.logdebug(
            "Transitioning CommState from %s to %s",
            CommState.to_string(self.state),
            CommState.to_string(state),
        )
        self.state = state

    def transition_to(self, state: int) -> None:
        rospy.logdebug(
            "Transitioning to %s (from %s, goal: %s)",
            CommState.to_string(state),
            CommState.to_string(self.state),
            self.goal_id,
        )
        self.state = state
        if self.transition_cb:
            self.transition_cb(ClientGoalHandle(self))

    def update_status(self, status_array: Any) -> None:
        with self.mutex:
            if self.state == CommState.DONE:
                return
            status = next(
                (s for s in status_array.status_list if s.goal_id.id == self.goal_id), None
            )
            if status is None:
                if self.state in _EXPECT_LISTED:
                    self._mark_as_lost()
                return
            self.latest_goal_status = status
            table = _TRANSITIONS.get(self.state)
            if table is None:
                rospy.logerr(f"CommStateMachine is in a funny state: {self.state}")
                return
            if status.status not in table:
                rospy.logerr(f"Got an unknown status from the ActionServer: {status.status}")
                return
            steps = table[status.status]
            if steps is None:
                rospy.logerr(
                    f"Invalid goal status transition from {CommState.to_string(self.state)} "
                    f"to {GoalStatus.to_string(status.status)}"
                )
                return
            for step in steps:
                self.transition_to(step)

    def _mark_as_lost(self) -> None:
        self.latest_goal_status.status = GoalStatus.LOST
        self.transition_to(CommState.DONE)

    def update_result(self, action_result: Any) -> None:
        if action_result.status.goal_id.id != self.goal_id:
            return
        with self.mutex:
            self.latest_goal_status = action_result.status
            self.latest_result = action_result
            if self.state == CommState.DONE:
                rospy.logerr("Got a result when we were already in the DONE state")
                return
            # the result's status moves the goal on first, as a status message would
            self.update_status(GoalStatusArray(status_list=[action_result.status]))
            self.transition_to(CommState.DONE)

    def update_feedback(self, action_feedback: Any) -> None:
        if action_feedback.status.goal_id.id != self.goal_id:
            return
        if self.feedback_cb and self.state != CommState.DONE:
            self.feedback_cb(ClientGoalHandle(self), action_feedback.feedback)


class ClientGoalHandle:
    """The client's handle on one goal it sent (equal handles track the same goal)."""

    def __init__(self, comm_state_machine: CommStateMachine | None) -> None:
        self.comm_state_machine = comm_state_machine

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ClientGoalHandle):
            return False
        return self.comm_state_machine == other.comm_state_machine

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return hash(self.comm_state_machine)

    def cancel(self) -> None:
        """Ask the server to cancel this goal."""
        csm = self.comm_state_machine
        if csm is None:
            return
        with csm.mutex:
            csm.send_cancel_fn(GoalID(stamp=rospy.Time(0), id=csm.goal_id))
            csm.transition_to(CommState.WAITING_FOR_CANCEL_ACK)

    def get_comm_state(self) -> int:
        if not self.comm_state_machine:
            rospy.logerr("Trying to get_comm_state on an inactive ClientGoalHandle.")
            return CommState.LOST
        return self.comm_state_machine.state

    def get_goal_status(self) -> int:
        if not self.comm_state_machine:
            rospy.logerr("Trying to get_goal_status on an inactive ClientGoalHandle.")
            return int(GoalStatus.PENDING)
        return int(self.comm_state_machine.latest_goal_status.status)

    def get_goal_status_text(self) -> str:
        if not self.comm_state_machine:
            text = "Trying to get_goal_status_text on an inactive ClientGoalHandle."
            rospy.logerr(text)
            return f"ERROR: {text}"
        return str(self.comm_state_machine.latest_goal_status.text)

    def get_result(self) -> Any:
        """The goal's ``*Result``, or None before one came."""
        if not self.comm_state_machine:
            rospy.logerr("Trying to get_result on an inactive ClientGoalHandle.")
            return None
        latest = self.comm_state_machine.latest_result
        return None if latest is None else latest.result

    def get_terminal_state(self) -> int:
        csm = self.comm_state_machine
        if not csm:
            rospy.logerr("Trying to get_terminal_state on an inactive ClientGoalHandle.")
            return int(GoalStatus.LOST)
        with csm.mutex:
            if csm.state != CommState.DONE:
                rospy.logwarn(
                    "Asking for the terminal state when we're in [%s]",
                    CommState.to_string(csm.state),
                )
            status = int(csm.latest_goal_status.status)
            if status in _TERMINAL_STATUSES:
                return status
            rospy.logerr("Asking for a terminal state, but the goal status is %d", status)
            return int(GoalStatus.LOST)


class GoalManager:
    """Makes goals and keeps a weak reference to each one's state machine: a goal nobody
    holds a handle to is no longer followed."""

    def __init__(self, action_spec: Any) -> None:
        self.list_mutex = threading.RLock()
        self.statuses: list[weakref.ref[CommStateMachine]] = []
        self.send_goal_fn: Callable[[Any], object] | None = None
        self.cancel_fn: Callable[[Any], object] | None = None
        wire = action_types(action_spec)
        self.ActionSpec = action_spec
        self.ActionGoal = wire.goal
        self.ActionResult = wire.result
        self.ActionFeedback = wire.feedback

    def _generate_id(self) -> Any:
        with _goal_numbers_lock:
            number = next(_goal_numbers)
        now = rospy.Time.now()
        return GoalID(id=f"{rospy.get_caller_id()}-{number}-{now.to_sec():.3f}", stamp=now)

    def register_send_goal_fn(self, fn: Callable[[Any], object]) -> None:
        self.send_goal_fn = fn

    def register_cancel_fn(self, fn: Callable[[Any], object]) -> None:
        self.cancel_fn = fn

    def init_goal(
        self,
        goal: Any,
        transition_cb: TransitionCallback | None = None,
        feedback_cb: FeedbackCallback | None = None,
    ) -> ClientGoalHandle:
        """Send ``goal`` and follow it; returns its handle."""
        action_goal = self.ActionGoal(goal_id=self._generate_id(), goal=goal)
        action_goal.header.stamp = rospy.get_rostime()
        assert self.send_goal_fn is not None
        assert self.cancel_fn is not None
        csm = CommStateMachine(
            action_goal, transition_cb, feedback_cb, self.send_goal_fn, self.cancel_fn
        )
        with self.list_mutex:
            self.statuses.append(weakref.ref(csm))
        self.send_goal_fn(action_goal)
        return ClientGoalHandle(csm)

    def _get_live_statuses(self) -> list[CommStateMachine]:
        with self.list_mutex:
            self.statuses = [r for r in self.statuses if r() is not None]
            return [csm for r in self.statuses if (csm := r()) is not None]

    def update_statuses(self, status_array: Any) -> None:
        for csm in self._get_live_statuses():
            csm.update_status(status_array)

    def update_results(self, action_result: Any) -> None:
        for csm in self._get_live_statuses():
            csm.update_result(action_result)

    def update_feedbacks(self, action_feedback: Any) -> None:
        for csm in self._get_live_statuses():
            csm.update_feedback(action_feedback)


def _queue_size(param: str, default: int | None) -> int | None:
    value = rospy.get_param(param, -1 if default is None else default)
    if not isinstance(value, int) or value < 0:
        return default
    return value


class ActionClient:
    """A client of the action server at ``ns`` for goals of ``ActionSpec`` (a ``*Action``
    message class); it may follow many goals at once."""

    def __init__(self, ns: str, ActionSpec: Any) -> None:  # noqa: N803 (actionlib's name)
        self.ns = ns
        self.last_status_msg: Any = None
        wire = action_types(ActionSpec)
        self.ActionSpec = ActionSpec
        self.ActionGoal = wire.goal
        self.ActionResult = wire.result
        self.ActionFeedback = wire.feedback
        base = rospy.remap_name(ns)
        self.pub_queue_size = _queue_size("actionlib_client_pub_queue_size", 10)
        self.pub_goal = rospy.Publisher(
            base + "/goal", self.ActionGoal, queue_size=self.pub_queue_size
        )
        self.pub_cancel = rospy.Publisher(base + "/cancel", GoalID, queue_size=self.pub_queue_size)
        self.manager = GoalManager(ActionSpec)
        self.manager.register_send_goal_fn(self.pub_goal.publish)
        self.manager.register_cancel_fn(self.pub_cancel.publish)
        self.sub_queue_size = _queue_size("actionlib_client_sub_queue_size", None)
        self.result_sub = rospy.Subscriber(
            base + "/result", self.ActionResult, self._result_cb, queue_size=self.sub_queue_size
        )
        self.feedback_sub = rospy.Subscriber(
            base + "/feedback",
            self.ActionFeedback,
            self._feedback_cb,
            queue_size=self.sub_queue_size,
        )
        # status last: its first message must find the result and feedback subscriptions made
        self.status_sub = rospy.Subscriber(
            base + "/status", GoalStatusArray, self._status_cb, queue_size=self.sub_queue_size
        )

    def stop(self) -> None:
        """Leave the action's topics."""
        for endpoint in (
            self.pub_goal,
            self.pub_cancel,
            self.status_sub,
            self.result_sub,
            self.feedback_sub,
        ):
            endpoint.unregister()

    def send_goal(
        self,
        goal: Any,
        transition_cb: TransitionCallback | None = None,
        feedback_cb: FeedbackCallback | None = None,
    ) -> ClientGoalHandle:
        """Send ``goal`` (a ``*Goal`` message); ``transition_cb(handle)`` is called on each
        change of its communication state, ``feedback_cb(handle, feedback)`` on feedback."""
        return self.manager.init_goal(goal, transition_cb, feedback_cb)

    def cancel_all_goals(self) -> None:
        """Ask the server to cancel every goal it has (from any client)."""
        self.pub_cancel.publish(GoalID(stamp=rospy.Time.from_sec(0.0), id=""))

    def cancel_goals_at_and_before_time(self, time: Any) -> None:
        """Ask the server to cancel every goal stamped at or before ``time``."""
        self.pub_cancel.publish(GoalID(stamp=time, id=""))

    def wait_for_action_server_to_start(self, timeout: Any = None) -> bool:
        """Deprecated name of :meth:`wait_for_server`."""
        return self.wait_for_server(timeout)

    def wait_for_server(self, timeout: Any = None) -> bool:
        """Wait until a server has said it is there (its status came) and takes goals and
        cancels; ``timeout`` (a Duration, zero: forever) in ROS time."""
        if timeout is None:
            timeout = rospy.Duration(0.0)
        forever = timeout == rospy.Duration(0.0)
        deadline = rospy.get_rostime() + timeout
        while not rospy.is_shutdown():
            if self.last_status_msg is not None and self._connected():
                return True
            if not forever and rospy.get_rostime() >= deadline:
                break
            time.sleep(0.01)
        return False

    def _connected(self) -> bool:
        # actionlib also checks that the server's result and feedback publishers reached this
        # client's subscribers. Here the status that came is that check: this client's
        # subscriptions were all made before it, and a publisher sends to every subscription
        # it knows of, not over connections of its own.
        return self.pub_goal.get_num_connections() > 0 and self.pub_cancel.get_num_connections() > 0

    def _status_cb(self, msg: Any) -> None:
        self.last_status_msg = msg
        self.manager.update_statuses(msg)

    def _result_cb(self, msg: Any) -> None:
        self.manager.update_results(msg)

    def _feedback_cb(self, msg: Any) -> None:
        self.manager.update_feedbacks(msg)
