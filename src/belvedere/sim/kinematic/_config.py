"""The ArbotiX driver's parameters, read and checked as ``arbotix_driver`` reads them.

Parameters live under the driver node's private namespace (``~rate``, ``~controllers/…``,
``~joints/…``), usually loaded from a YAML file. Checking happens up front, so a bad file is one
error at its line instead of the original's log line and a silently missing controller.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, Final

from belvedere.errors import ParseError, SourceLocation
from belvedere.yamlfile import YamlDocument

__all__ = [
    "ArbotixConfig",
    "ArbotixConfigError",
    "DiffControllerConfig",
    "FollowControllerConfig",
    "Locator",
    "ServoConfig",
    "param_locator",
]

Locator = Callable[..., SourceLocation]
"""``locate(*keys)``: where the value at ``keys`` (below the driver's namespace) came from."""

CONTROLLER_TYPES: Final = ("diff_controller", "follow_controller")
HARDWARE_ONLY_TYPES: Final = ("linear_controller", "linear_controller_i")
SERVO_TYPES: Final = ("dynamixel", "hobby_servo")


class ArbotixConfigError(ParseError):
    """A driver parameter is missing or has the wrong type."""


def param_locator(namespace: str) -> Locator:
    """Locations for parameters that came from the parameter tree (named by their path)."""

    def locate(*keys: str | int) -> SourceLocation:
        path = "/".join([namespace.rstrip("/"), *map(str, keys)])
        return SourceLocation(f"parameter {path}")

    return locate


@dataclass(frozen=True)
class DiffControllerConfig:
    """``type: diff_controller``. Only rate and the frames matter in fake mode; the rest is
    kept (and checked) as the original reads it."""

    name: str
    ticks_meter: float
    base_width: float
    rate: float = 10.0
    timeout: float = 1.0
    base_frame_id: str = "base_link"
    odom_frame_id: str = "odom"
    Kp: float = 5
    Kd: float = 1
    Ki: float = 0
    Ko: float = 50
    accel_limit: float = 0.1
    cmd_vel_timeout: float = 0.0
    """belvedere's own: stop after this many quiet seconds (0: never, as the original)."""


@dataclass(frozen=True)
class FollowControllerConfig:
    """``type: follow_controller``: a FollowJointTrajectory action over servo joints."""

    name: str
    joints: tuple[str, ...]
    rate: float = 50.0
    action_name: str = "follow_joint_trajectory"


@dataclass(frozen=True)
class ServoConfig:
    """One entry of ``~joints``: a Dynamixel or hobby servo (angles in radians here)."""

    name: str
    type: str
    id: int
    ticks: int
    neutral: float
    range_deg: float
    min_angle: float
    max_angle: float
    max_speed: float
    """rad/s"""
    invert: bool
    readable: bool

    @property
    def rad_per_tick(self) -> float:
        return math.radians(self.range_deg) / self.ticks

    def clamp(self, angle: float) -> float:
        """The angle the servo can reach: its tick range bounds it, as the original's
        angleToTicks/ticksToAngle round trip does (min/max_angle are not applied there)."""
        sign = -1.0 if self.invert else 1.0
        ticks = self.neutral + sign * angle / self.rad_per_tick
        ticks = min(max(ticks, 0.0), self.ticks - 1.0)
        return sign * (ticks - self.neutral) * self.rad_per_tick


@dataclass(frozen=True)
class ArbotixConfig:
    """Everything ``arbotix_driver`` reads under its private namespace."""

    sim: bool = False
    rate: float = 100.0
    read_rate: float = 10.0
    write_rate: float = 10.0
    diagnostic_rate: float = 1.0
    joints: tuple[ServoConfig, ...] = ()
    controllers: tuple[DiffControllerConfig | FollowControllerConfig, ...] = ()
    skipped: tuple[str, ...] = ()
    """Controllers that only make sense with hardware (named, with why)."""

    @classmethod
    def from_yaml(cls, doc: YamlDocument) -> ArbotixConfig:
        """From a YAML file loaded into the driver's namespace (``rosparam load``)."""
        if doc.data is None:
            return cls()
        return cls.from_params(doc.data, locate=doc.location)

    @classmethod
    def from_params(cls, params: Any, *, locate: Locator | None = None) -> ArbotixConfig:
        """From the driver's private parameters (a mapping)."""
        reader = _Reader(locate or param_locator("~"))
        root = reader.mapping(params, ())
        joints = tuple(
            _servo(reader, name, value)
            for name, value in reader.mapping(root.get("joints", {}), ("joints",)).items()
        )
        controllers: list[DiffControllerConfig | FollowControllerConfig] = []
        skipped: list[str] = []
        entries = reader.mapping(root.get("controllers", {}), ("controllers",))
        for name, value in entries.items():
            keys = ("controllers", name)
            entry = reader.mapping(value, keys)
            kind = reader.string(entry, keys, "type", None)
            if kind == "diff_controller":
                controllers.append(_diff(reader, str(name), entry))
            elif kind == "follow_controller":
                controllers.append(_follow(reader, str(name), entry, joints))
            elif kind in HARDWARE_ONLY_TYPES:
                skipped.append(f"{name} ({kind} reads ArbotiX analog inputs: hardware only)")
            else:
                known = ", ".join(CONTROLLER_TYPES + HARDWARE_ONLY_TYPES)
                msg = f"controller {name!r}: unknown type {kind!r} (known: {known})"
                raise ArbotixConfigError(msg, reader.locate(*keys, "type"))
        return cls(
            sim=reader.boolean(root, (), "sim", False),
            rate=reader.positive(root, (), "rate", 100.0),
            read_rate=reader.positive(root, (), "read_rate", 10.0),
            write_rate=reader.positive(root, (), "write_rate", 10.0),
            diagnostic_rate=reader.positive(root, (), "diagnostic_rate", 1.0),
            joints=joints,
            controllers=tuple(controllers),
            skipped=tuple(skipped),
        )


_REQUIRED: Final[Any] = object()


class _Reader:
    """Typed access to nested parameters, with errors at the value's location."""

    def __init__(self, locate: Locator) -> None:
        self.locate = locate

    def fail(self, keys: tuple[Any, ...], what: str, value: Any) -> ArbotixConfigError:
        path = "/".join(map(str, keys))
        msg = f"parameter {path}: expected {what}, got {value!r}"
        return ArbotixConfigError(msg, self.locate(*keys))

    def mapping(self, value: Any, keys: tuple[Any, ...]) -> Mapping[str, Any]:
        if not isinstance(value, Mapping):
            raise self.fail(keys, "a mapping of names to settings", value)
        return value

    def get(self, entry: Mapping[str, Any], keys: tuple[Any, ...], key: str, default: Any) -> Any:
        if key in entry:
            return entry[key]
        if default is _REQUIRED:
            owner = "/".join(map(str, keys)) or "the driver"
            msg = f"{owner}: required parameter {key!r} is missing"
            raise ArbotixConfigError(msg, self.locate(*keys))
        return default

    def number(
        self, entry: Mapping[str, Any], keys: tuple[Any, ...], key: str, default: Any
    ) -> float:
        value = self.get(entry, keys, key, default)
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise self.fail((*keys, key), "a number", value)
        return float(value)

    def positive(
        self, entry: Mapping[str, Any], keys: tuple[Any, ...], key: str, default: Any
    ) -> float:
        value = self.number(entry, keys, key, default)
        if value <= 0:
            raise self.fail((*keys, key), "a positive number", value)
        return value

    def boolean(
        self, entry: Mapping[str, Any], keys: tuple[Any, ...], key: str, default: bool
    ) -> bool:
        value = self.get(entry, keys, key, default)
        if isinstance(value, str) and value.lower() in ("true", "false"):
            return value.lower() == "true"
        if not isinstance(value, bool | int):
            raise self.fail((*keys, key), "true or false", value)
        return bool(value)

    def string(
        self, entry: Mapping[str, Any], keys: tuple[Any, ...], key: str, default: str | None
    ) -> str:
        value = self.get(entry, keys, key, _REQUIRED if default is None else default)
        if not isinstance(value, str) or not value:
            raise self.fail((*keys, key), "a name", value)
        return value


def _diff(reader: _Reader, name: str, entry: Mapping[str, Any]) -> DiffControllerConfig:
    keys = ("controllers", name)
    return DiffControllerConfig(
        name=name,
        ticks_meter=reader.number(entry, keys, "ticks_meter", _REQUIRED),
        base_width=reader.number(entry, keys, "base_width", _REQUIRED),
        rate=reader.positive(entry, keys, "rate", 10.0),
        timeout=reader.number(entry, keys, "timeout", 1.0),
        base_frame_id=reader.string(entry, keys, "base_frame_id", "base_link"),
        odom_frame_id=reader.string(entry, keys, "odom_frame_id", "odom"),
        Kp=reader.number(entry, keys, "Kp", 5),
        Kd=reader.number(entry, keys, "Kd", 1),
        Ki=reader.number(entry, keys, "Ki", 0),
        Ko=reader.number(entry, keys, "Ko", 50),
        accel_limit=reader.number(entry, keys, "accel_limit", 0.1),
        cmd_vel_timeout=max(0.0, reader.number(entry, keys, "cmd_vel_timeout", 0.0)),
    )


def _follow(
    reader: _Reader, name: str, entry: Mapping[str, Any], servos: tuple[ServoConfig, ...]
) -> FollowControllerConfig:
    keys = ("controllers", name)
    joints = reader.get(entry, keys, "joints", _REQUIRED)
    if not isinstance(joints, list) or not all(isinstance(j, str) for j in joints):
        raise reader.fail((*keys, "joints"), "a list of joint names", joints)
    known = {s.name for s in servos}
    for i, joint in enumerate(joints):
        if joint not in known:
            msg = (
                f"controller {name!r}: joint {joint!r} is not one of the driver's joints "
                f"({', '.join(sorted(known)) or 'none are defined under joints:'})"
            )
            raise ArbotixConfigError(msg, reader.locate(*keys, "joints", i))
    return FollowControllerConfig(
        name=name,
        joints=tuple(joints),
        rate=reader.positive(entry, keys, "rate", 50.0),
        action_name=reader.string(entry, keys, "action_name", "follow_joint_trajectory"),
    )


def _servo(reader: _Reader, name: str, value: Any) -> ServoConfig:
    keys = ("joints", name)
    entry = reader.mapping(value if value is not None else {}, keys)
    kind = reader.string(entry, keys, "type", "dynamixel")
    if kind not in SERVO_TYPES:
        hint = "calibrated_linear joints need hardware" if kind == "calibrated_linear" else ""
        msg = f"joint {name!r}: unsupported type {kind!r} (known: {', '.join(SERVO_TYPES)})"
        raise ArbotixConfigError(msg, reader.locate(*keys, "type"), hint=hint or None)
    hobby = kind == "hobby_servo"
    ticks = int(reader.positive(entry, keys, "ticks", 2000 if hobby else 1024))
    default_range = 180.0 if hobby else (360.0 if ticks == 4096 else 300.0)
    span = reader.positive(entry, keys, "range", default_range)
    return ServoConfig(
        name=str(name),
        type=kind,
        id=int(reader.number(entry, keys, "id", _REQUIRED)),
        ticks=ticks,
        neutral=reader.number(entry, keys, "neutral", 1500 if hobby else ticks // 2),
        range_deg=span,
        min_angle=math.radians(reader.number(entry, keys, "min_angle", -span / 2)),
        max_angle=math.radians(reader.number(entry, keys, "max_angle", span / 2)),
        max_speed=math.radians(reader.positive(entry, keys, "max_speed", 90.0 if hobby else 684.0)),
        invert=reader.boolean(entry, keys, "invert", False),
        readable=reader.boolean(entry, keys, "readable", True),
    )
