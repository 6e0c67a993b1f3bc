"""The state names of actionlib: the client's communication states, the simple client's three
states, the terminal states, and the ``actionlib_msgs`` message classes they are read from.

As actionlib does, importing this gives ``GoalStatus`` a ``to_string`` class method.
"""

from __future__ import annotations

from typing import Any

from belvedere.errors import BelvedereError
from belvedere.ros1._classes import message_class

__all__ = [
    "ActionException",
    "CommState",
    "GoalID",
    "GoalStatus",
    "GoalStatusArray",
    "SimpleGoalState",
    "TerminalState",
    "get_name_of_constant",
]

GoalID: Any = message_class("actionlib_msgs/GoalID")
GoalStatus: Any = message_class("actionlib_msgs/GoalStatus")
GoalStatusArray: Any = message_class("actionlib_msgs/GoalStatusArray")


class ActionException(BelvedereError):  # noqa: N818 (actionlib's name, which scripts catch)
    """A type given as an action spec is not one (it has no ``action_goal``, ...)."""


def get_name_of_constant(cls: type, value: int) -> str:
    """The name of the integer constant of ``cls`` equal to ``value``
    (``NO_SUCH_STATE_<value>`` when none is).

    Only public upper-case names count: actionlib's own lookup also sees a message class's
    ``_has_header`` flag (False == 0) and names PENDING ``_has_header``."""
    for klass in cls.__mro__:
        for name, constant in vars(klass).items():
            if (
                name.isupper()
                and isinstance(constant, int)
                and not isinstance(constant, bool)
                and constant == value
            ):
                return name
    return f"NO_SUCH_STATE_{value}"


class _Named:
    """States as class attributes, with ``to_string(value)`` as actionlib gives them."""

    @classmethod
    def to_string(cls, value: int) -> str:
        return get_name_of_constant(cls, value)


class CommState(_Named):
    """Where a goal is in its exchange with the server, as a client sees it."""

    WAITING_FOR_GOAL_ACK = 0
    PENDING = 1
    ACTIVE = 2
    WAITING_FOR_RESULT = 3
    WAITING_FOR_CANCEL_ACK = 4
    RECALLING = 5
    PREEMPTING = 6
    DONE = 7
    LOST = 8


class TerminalState(_Named):
    """The statuses a goal can end in (``GoalStatus`` values)."""

    RECALLED: int = GoalStatus.RECALLED
    REJECTED: int = GoalStatus.REJECTED
    PREEMPTED: int = GoalStatus.PREEMPTED
    ABORTED: int = GoalStatus.ABORTED
    SUCCEEDED: int = GoalStatus.SUCCEEDED
    LOST: int = GoalStatus.LOST


class SimpleGoalState(_Named):
    """The simple client's view of its one goal."""

    PENDING = 0
    ACTIVE = 1
    DONE = 2


GoalStatus.to_string = classmethod(get_name_of_constant)
