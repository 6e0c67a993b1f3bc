"""actionlib, as ROS 1 speaks it: goals, cancels, status, feedback and results as topics.

An action ``ns`` of type ``pkg/Name`` uses ``ns/goal`` (``pkg/NameActionGoal``), ``ns/cancel``
(``actionlib_msgs/GoalID``), ``ns/status`` (``actionlib_msgs/GoalStatusArray``, 5 Hz),
``ns/feedback`` and ``ns/result``. The server behaves as actionlib's SimpleActionServer: one
goal runs at a time and a new goal asks the running one to stop (preempt) before it starts.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from enum import IntEnum
from typing import Any

from belvedere.graph._executor import NS
from belvedere.graph._graph import Node
from belvedere.msgs import message_from_data

__all__ = ["ActionClient", "ActionServer", "GoalHandle", "GoalStatus"]

_STATUS_KEEP_NS = 5 * NS  # actionlib's status_list_timeout


class GoalStatus(IntEnum):
    PENDING = 0
    ACTIVE = 1
    PREEMPTED = 2
    SUCCEEDED = 3
    ABORTED = 4
    REJECTED = 5
    PREEMPTING = 6
    RECALLING = 7
    RECALLED = 8
    LOST = 9


_TERMINAL = frozenset(
    {
        GoalStatus.PREEMPTED,
        GoalStatus.SUCCEEDED,
        GoalStatus.ABORTED,
        GoalStatus.REJECTED,
        GoalStatus.RECALLED,
    }
)


def _stamp(ns: int) -> list[int]:
    return [ns // NS, ns % NS]


class GoalHandle:
    """One goal on a server: the goal message, its status, and the calls that end it."""

    def __init__(self, server: ActionServer, goal_id: str, stamp_ns: int, goal: Any) -> None:
        self.server = server
        self.id = goal_id
        self.stamp_ns = stamp_ns
        self.goal = goal
        self.status = GoalStatus.PENDING
        self.text = ""
        self.cancel_requested = False
        self.ended_ns: int | None = None

    @property
    def active(self) -> bool:
        return self.status in (GoalStatus.ACTIVE, GoalStatus.PREEMPTING)

    def publish_feedback(self, feedback: dict[str, Any]) -> None:
        self.server.send_feedback(self, feedback)

    def succeed(self, result: dict[str, Any] | None = None, text: str = "") -> None:
        self.server.finish(self, GoalStatus.SUCCEEDED, result, text)

    def abort(self, result: dict[str, Any] | None = None, text: str = "") -> None:
        self.server.finish(self, GoalStatus.ABORTED, result, text)

    def preempted(self, result: dict[str, Any] | None = None, text: str = "") -> None:
        """End after a cancel or a newer goal (RECALLED if it never started)."""
        status = GoalStatus.PREEMPTED if self.active else GoalStatus.RECALLED
        self.server.finish(self, status, result, text)


class ActionServer:
    """Serves action ``name`` of ``action_type`` (``pkg/Name``); ``execute`` is called with
    each goal when it becomes active and must end it (now or later) with succeed/abort/
    preempted, watching ``cancel_requested``."""

    def __init__(
        self,
        node: Node,
        name: str,
        action_type: str,
        execute: Callable[[GoalHandle], object],
        *,
        status_frequency: float = 5.0,
    ) -> None:
        self.node = node
        self.name = node.resolve(name)
        self.type = action_type
        self.execute = execute
        self.goals: dict[str, GoalHandle] = {}
        self.current: GoalHandle | None = None
        self.next: GoalHandle | None = None
        base = f"{self.name}/"
        self.status_pub = node.publisher(
            base + "status", "actionlib_msgs/GoalStatusArray", queue_size=50
        )
        self.feedback_pub = node.publisher(
            base + "feedback", f"{action_type}ActionFeedback", queue_size=50
        )
        self.result_pub = node.publisher(
            base + "result", f"{action_type}ActionResult", queue_size=50
        )
        node.subscribe(base + "goal", f"{action_type}ActionGoal", self._on_goal, queue_size=50)
        node.subscribe(base + "cancel", "actionlib_msgs/GoalID", self._on_cancel, queue_size=50)
        node.timer(1.0 / status_frequency, self.publish_status)

    # --- incoming ------------------------------------------------------------------------------
    def _on_goal(self, msg: Any) -> None:
        now = self.node.now_ns()
        stamp = msg.goal_id.stamp
        stamp_ns = stamp.sec * NS + stamp.nanosec or now
        goal_id = msg.goal_id.id or f"{self.node.full_name}-{now}"
        if goal_id in self.goals:
            return  # a repeated goal: actionlib ignores it too
        handle = GoalHandle(self, goal_id, stamp_ns, msg.goal)
        self.goals[goal_id] = handle
        if self.next is not None:  # an unstarted newer goal replaces an older pending one
            self.next.preempted(text="replaced by a newer goal")
        if self.current is not None and self.current.active:
            self.current.cancel_requested = True
            self.current.status = GoalStatus.PREEMPTING
            self.next = handle
        else:
            self._start(handle)
        self.publish_status()

    def _on_cancel(self, msg: Any) -> None:
        stamp_ns = msg.stamp.sec * NS + msg.stamp.nanosec
        for handle in list(self.goals.values()):
            if handle.status in _TERMINAL:
                continue
            by_id = bool(msg.id) and handle.id == msg.id
            everything = not msg.id and stamp_ns == 0
            before = stamp_ns != 0 and handle.stamp_ns <= stamp_ns
            if by_id or everything or before:
                if handle is self.current:
                    handle.cancel_requested = True
                    handle.status = GoalStatus.PREEMPTING
                else:
                    handle.preempted(text="canceled before it started")
        self.publish_status()

    def _start(self, handle: GoalHandle) -> None:
        self.current = handle
        handle.status = GoalStatus.ACTIVE
        self.execute(handle)

    # --- outgoing ------------------------------------------------------------------------------
    def finish(
        self, handle: GoalHandle, status: GoalStatus, result: dict[str, Any] | None, text: str
    ) -> None:
        if handle.status in _TERMINAL:
            return
        handle.status = status
        handle.text = text
        handle.ended_ns = self.node.now_ns()
        self.result_pub.publish(
            message_from_data(
                f"{self.type}ActionResult",
                {
                    "header": {"stamp": _stamp(handle.ended_ns)},
                    "status": self._status_data(handle),
                    "result": result or {},
                },
            )
        )
        if handle is self.next:
            self.next = None
        if handle is self.current:
            self.current = None
            pending, self.next = self.next, None
            if pending is not None:
                self._start(pending)
        self.publish_status()

    def send_feedback(self, handle: GoalHandle, feedback: dict[str, Any]) -> None:
        self.feedback_pub.publish(
            message_from_data(
                f"{self.type}ActionFeedback",
                {
                    "header": {"stamp": _stamp(self.node.now_ns())},
                    "status": self._status_data(handle),
                    "feedback": feedback,
                },
            )
        )

    def _status_data(self, handle: GoalHandle) -> dict[str, Any]:
        return {
            "goal_id": {"stamp": _stamp(handle.stamp_ns), "id": handle.id},
            "status": int(handle.status),
            "text": handle.text,
        }

    def publish_status(self) -> None:
        now = self.node.now_ns()
        for goal_id, handle in list(self.goals.items()):
            if handle.ended_ns is not None and now - handle.ended_ns > _STATUS_KEEP_NS:
                del self.goals[goal_id]
        self.status_pub.publish(
            message_from_data(
                "actionlib_msgs/GoalStatusArray",
                {
                    "header": {"stamp": _stamp(now)},
                    "status_list": [self._status_data(h) for h in self.goals.values()],
                },
            )
        )


class ActionClient:
    """Sends goals to an action server and keeps what it hears about them."""

    _ids = itertools.count(1)

    def __init__(self, node: Node, name: str, action_type: str) -> None:
        self.node = node
        self.name = node.resolve(name)
        self.type = action_type
        base = f"{self.name}/"
        self.goal_pub = node.publisher(base + "goal", f"{action_type}ActionGoal", queue_size=10)
        self.cancel_pub = node.publisher(base + "cancel", "actionlib_msgs/GoalID", queue_size=10)
        self.status: dict[str, GoalStatus] = {}
        self.results: dict[str, Any] = {}
        self.feedback: dict[str, list[Any]] = {}
        node.subscribe(base + "status", "actionlib_msgs/GoalStatusArray", self._on_status)
        node.subscribe(
            base + "result", f"{action_type}ActionResult", self._on_result, queue_size=50
        )
        node.subscribe(
            base + "feedback", f"{action_type}ActionFeedback", self._on_feedback, queue_size=50
        )

    def send_goal(self, goal: dict[str, Any]) -> str:
        """Send ``goal`` (message data); returns its id."""
        now = self.node.now_ns()
        goal_id = f"{self.node.full_name}-{next(self._ids)}-{now}"
        self.status[goal_id] = GoalStatus.PENDING
        self.goal_pub.publish(
            message_from_data(
                f"{self.type}ActionGoal",
                {
                    "header": {"stamp": _stamp(now)},
                    "goal_id": {"stamp": _stamp(now), "id": goal_id},
                    "goal": goal,
                },
            )
        )
        return goal_id

    def cancel(self, goal_id: str = "") -> None:
        """Cancel one goal, or every goal with an empty id."""
        self.cancel_pub.publish(message_from_data("actionlib_msgs/GoalID", {"id": goal_id}))

    def done(self, goal_id: str) -> bool:
        return goal_id in self.results

    def _on_status(self, msg: Any) -> None:
        for status in msg.status_list:
            if status.goal_id.id in self.status and status.goal_id.id not in self.results:
                self.status[status.goal_id.id] = GoalStatus(status.status)

    def _on_result(self, msg: Any) -> None:
        goal_id = msg.status.goal_id.id
        if goal_id in self.status:
            self.status[goal_id] = GoalStatus(msg.status.status)
            self.results[goal_id] = msg

    def _on_feedback(self, msg: Any) -> None:
        goal_id = msg.status.goal_id.id
        if goal_id in self.status:
            self.feedback.setdefault(goal_id, []).append(msg.feedback)
