"""dynamic_reconfigure's message and service types (ROS 1 Noetic), in .msg syntax.

:mod:`belvedere.msgs._types` merges these into the store beside its other extra types.
"""

from __future__ import annotations

from typing import Final

__all__ = ["MESSAGES", "SERVICES"]

_PKG: Final = "dynamic_reconfigure"

MESSAGES: Final = {
    f"{_PKG}/msg/BoolParameter": "string name\nbool value",
    f"{_PKG}/msg/IntParameter": "string name\nint32 value",
    f"{_PKG}/msg/StrParameter": "string name\nstring value",
    f"{_PKG}/msg/DoubleParameter": "string name\nfloat64 value",
    f"{_PKG}/msg/GroupState": "string name\nbool state\nint32 id\nint32 parent",
    f"{_PKG}/msg/Config": (
        "dynamic_reconfigure/BoolParameter[] bools\n"
        "dynamic_reconfigure/IntParameter[] ints\n"
        "dynamic_reconfigure/StrParameter[] strs\n"
        "dynamic_reconfigure/DoubleParameter[] doubles\n"
        "dynamic_reconfigure/GroupState[] groups"
    ),
    f"{_PKG}/msg/ParamDescription": (
        "string name\nstring type\nuint32 level\nstring description\nstring edit_method"
    ),
    f"{_PKG}/msg/Group": (
        "string name\nstring type\ndynamic_reconfigure/ParamDescription[] parameters\n"
        "int32 parent\nint32 id"
    ),
    f"{_PKG}/msg/ConfigDescription": (
        "dynamic_reconfigure/Group[] groups\ndynamic_reconfigure/Config max\n"
        "dynamic_reconfigure/Config min\ndynamic_reconfigure/Config dflt"
    ),
    f"{_PKG}/msg/SensorLevels": (
        "byte RECONFIGURE_CLOSE=3\nbyte RECONFIGURE_STOP=1\nbyte RECONFIGURE_RUNNING=0"
    ),
}

SERVICES: Final = {
    f"{_PKG}/srv/Reconfigure": (
        "dynamic_reconfigure/Config config",
        "dynamic_reconfigure/Config config",
    ),
}
