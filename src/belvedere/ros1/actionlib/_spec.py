"""The three wire types of an action, read from its ``*Action`` message class as actionlib
reads them: from the types of an instance's ``action_goal``, ``action_result`` and
``action_feedback``."""

from __future__ import annotations

from typing import Any, NamedTuple

from belvedere.ros1.actionlib._states import ActionException

__all__ = ["ActionTypes", "action_types"]


class ActionTypes(NamedTuple):
    goal: type[Any]
    """``<pkg>/<Name>ActionGoal``"""
    result: type[Any]
    """``<pkg>/<Name>ActionResult``"""
    feedback: type[Any]
    """``<pkg>/<Name>ActionFeedback``"""
    result_body: type[Any]
    """``<pkg>/<Name>Result``, the default result of a goal ended without one."""


def action_types(action_spec: Any) -> ActionTypes:
    """The wire types of ``action_spec`` (a ``*Action`` class), or :class:`ActionException`."""
    try:
        spec = action_spec()
        return ActionTypes(
            type(spec.action_goal),
            type(spec.action_result),
            type(spec.action_feedback),
            type(spec.action_result.result),
        )
    except (AttributeError, TypeError):  # actionlib lets TypeError (a non-class) through
        msg = f"Type is not an action spec: {action_spec}"
        raise ActionException(msg) from None
