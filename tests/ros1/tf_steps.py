"""Running a tf scenario's steps (``tests/ros1/tf_scenarios.py`` describes them) on one side:
belvedere's classes in the tests, Debian's in ``tf_oracle.py`` — which Debian's
``/usr/bin/python3`` runs, so this module needs only the standard library."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any


def error(err: BaseException) -> dict[str, Any]:
    """What a step that raised answers: the exception's type and text."""
    return {"error": [type(err).__name__, str(err)]}


class Steps:
    """Steps run on one side: its ``rospy`` makes times and durations, ``message_class``
    finds a message class by its ``pkg/Type``, ``encode`` answers a plain value."""

    def __init__(
        self, rospy: Any, message_class: Callable[[str], Any], encode: Callable[[Any], Any]
    ) -> None:
        self._rospy = rospy
        self._message_class = message_class
        self._encode = encode

    def message(self, spec: dict[str, Any]) -> Any:
        """``{"msg": "pkg/Type", "fields": {...}}`` as a message of this side's classes."""
        msg = self._message_class(spec["msg"])()
        for field, value in spec["fields"].items():
            setattr(msg, field, self.argument(value))
        return msg

    def argument(self, value: Any) -> Any:
        """A step's argument: times, durations and messages are tagged dictionaries."""
        if isinstance(value, dict) and "time" in value:
            return self._rospy.Time(*value["time"])
        if isinstance(value, dict) and "duration" in value:
            return self._rospy.Duration(*value["duration"])
        if isinstance(value, dict) and "msg" in value:
            return self.message(value)
        if isinstance(value, list):
            return [self.argument(v) for v in value]
        return value

    def result(self, value: Any) -> Any:
        """A step's result; messages field by field, times as [secs, nsecs]."""
        if hasattr(value, "_type") and hasattr(value, "__slots__"):
            return {
                "msg": value._type,
                "fields": {s: self.result(getattr(value, s)) for s in value.__slots__},
            }
        if hasattr(value, "secs") and hasattr(value, "nsecs"):
            return {"time": [value.secs, value.nsecs]}
        if isinstance(value, list | tuple):
            items = [self.result(v) for v in value]
            return items if isinstance(value, list) else {"tuple": items}
        return self._encode(value)

    def run(self, target: Any, steps: list[Any]) -> list[Any]:
        """Each step's result (or error) of calling ``target``'s methods in turn."""
        out = []
        for name, *args in steps:
            try:
                out.append(self.result(getattr(target, name)(*[self.argument(a) for a in args])))
            except Exception as err:  # noqa: BLE001 (compares whatever is raised)
                out.append(error(err))
        return out
