"""Messages from YAML as ``rostopic pub`` takes them, and to YAML as ``rostopic echo`` prints.

Input: a mapping by field name (missing fields are zero), or positional values (a list, or
one command-line argument per field), ``header: auto`` (stamp now, sequence numbered),
``now`` for a time field, ``{}`` for all defaults. A wrong field or value is an error naming
the field path, the expected type and the value given.
"""

from __future__ import annotations

import math
import struct
import sys
from collections.abc import Callable, Sequence
from typing import Any, Final

import numpy as np
import yaml

from belvedere.errors import BelvedereError
from belvedere.msgs._types import PLACEHOLDER, TypeRegistry, short, types
from belvedere.yamlfile import Loader

__all__ = [
    "MessageValueError",
    "default_message",
    "message_from_args",
    "message_from_data",
    "message_to_data",
    "message_to_yaml",
]

BASE, NAME, ARRAY, SEQUENCE = 1, 2, 3, 4

_INT_RANGES: Final = {
    "int8": (-(2**7), 2**7 - 1),
    "uint8": (0, 2**8 - 1),
    "byte": (-(2**7), 2**7 - 1),  # ROS 1's byte is a signed 8-bit integer (genpy's 'b')
    "char": (0, 2**8 - 1),
    "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1),
    "uint64": (0, 2**64 - 1),
}
NUMPY_DTYPES: Final = {
    "bool": np.bool_,
    "int8": np.int8,
    "uint8": np.uint8,
    "byte": np.int8,
    "char": np.uint8,
    "int16": np.int16,
    "uint16": np.uint16,
    "int32": np.int32,
    "uint32": np.uint32,
    "int64": np.int64,
    "uint64": np.uint64,
    "float32": np.float32,
    "float64": np.float64,
}
"""ROS 1's numeric field types as numpy dtypes (``byte`` is int8, ``char`` uint8)."""
_FLOAT_LIMITS: Final = {
    "float32": f"±{np.finfo(np.float32).max!s}",
    "float64": f"±{sys.float_info.max}",
}
_TIME: Final = ("builtin_interfaces/msg/Time", "builtin_interfaces/msg/Duration")
_TIME_SECONDS: Final = {
    "builtin_interfaces/msg/Time": (0, 2**31 - 1),
    "builtin_interfaces/msg/Duration": (-(2**31), 2**31 - 1),
}
NS: Final = 1_000_000_000
_HEADER: Final = "std_msgs/msg/Header"

Clock = Callable[[], tuple[int, int]]
"""Returns (seconds, nanoseconds) for ``now``/``header: auto``."""


class MessageValueError(BelvedereError):
    """A value that does not fit its message field."""


def _fail(path: str, expected: str, value: Any) -> MessageValueError:
    where = f"field {path!r}" if path else "message"
    return MessageValueError(f"{where}: expected {expected}, got {_show(value)}")


def _misfit(path: str, value: Any, typ: str, limits: str) -> MessageValueError:
    where = f"field {path!r}" if path else "message"
    return MessageValueError(f"{where}: {_show(value)} does not fit {typ} ({limits})")


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _show(value: Any) -> str:
    """``repr``, but a huge integer by its size (its digits say nothing, and Python refuses
    to print more than 4300 of them)."""
    if _is_int(value) and abs(value) >= 10**30:
        digits = int(abs(value).bit_length() * math.log10(2)) + 1
        if 10 ** (digits - 1) > abs(value):
            digits -= 1
        return f"a {digits}-digit integer"
    return repr(value)


class _Builder:
    def __init__(self, registry: TypeRegistry, clock: Clock | None, seq: int) -> None:
        self.reg = registry
        self.clock = clock
        self.seq = seq

    def now(self, path: str) -> tuple[int, int]:
        if self.clock is None:
            msg = f"field {path!r}: 'now'/'auto' needs a clock (none available here)"
            raise MessageValueError(msg)
        return self.clock()

    # --- messages ------------------------------------------------------------------------------
    def message(self, name: str, value: Any, path: str) -> Any:
        cls = self.reg.store.types[name]
        fields = self.reg.store.fielddefs[name][1]
        if name in _TIME:
            return self.time(cls, value, path)
        if name == _HEADER and value in ("auto", "now"):
            sec, nsec = self.now(path)
            return self.message(name, {"seq": self.seq, "stamp": [sec, nsec]}, path)
        if value is None:
            value = {}
        if isinstance(value, list | tuple):
            if len(value) > len(fields):
                got = f"{len(value)} values"
                raise _fail(path, f"at most {len(fields)} values for {short(name)}", got)
            value = {f[0]: v for f, v in zip(fields, value, strict=False)}
        if not isinstance(value, dict):
            raise _fail(path, f"a mapping or list for {short(name)}", value)
        known = {f[0] for f in fields}
        for key in value:
            if key not in known:
                sub = f"{path}.{key}" if path else str(key)
                msg = f"field {sub!r} does not exist in {short(name)}"
                hint = f"fields: {', '.join(f[0] for f in fields) or '(none)'}"
                raise MessageValueError(msg, hint=hint)
        args = {}
        for fname, (kind, detail) in fields:
            sub = f"{path}.{fname}" if path else fname
            args[fname] = self.field(kind, detail, value.get(fname, _MISSING), sub)
        return cls(**args)

    def time(self, cls: type[Any], value: Any, path: str) -> Any:
        if value is _MISSING or value is None:
            return cls(0, 0)
        if value == "now":
            return cls(*self.now(path))
        if isinstance(value, bool):
            raise _fail(path, "a time (seconds, 'now', or {secs, nsecs})", value)
        given = value
        if isinstance(value, int):
            total_ns = value * NS
        elif isinstance(value, float):
            if not math.isfinite(value):
                raise _fail(path, "a finite time", value)
            sec = math.floor(value)
            total_ns = int(sec) * NS + round((value - sec) * 1e9)
        else:
            if isinstance(value, list | tuple) and len(value) == 2:
                value = {"sec": value[0], "nanosec": value[1]}
            if not isinstance(value, dict):
                raise _fail(path, "a time (seconds, 'now', or {secs, nsecs})", value)
            secs: Any = value.get("sec", value.get("secs", 0))
            nsecs: Any = value.get("nanosec", value.get("nsecs", 0))
            extra = set(value) - {"sec", "secs", "nanosec", "nsecs"}
            if extra or not all(_is_int(v) for v in (secs, nsecs)):
                raise _fail(path, "{secs: int, nsecs: int}", value)
            total_ns = secs * NS + nsecs
        # As rospy does: nanoseconds carried into seconds (1 s - 1 ns is 0 s + 999999999 ns).
        sec, nanosec = divmod(total_ns, NS)
        low, high = _TIME_SECONDS[cls.__msgtype__]
        if not low <= sec <= high:
            what = "a time" if low == 0 else "a duration"
            raise _misfit(path, given, what, f"{low} to {high} s: int32 seconds on the wire")
        return cls(sec, nanosec)

    # --- fields --------------------------------------------------------------------------------
    def field(self, kind: int, detail: Any, value: Any, path: str) -> Any:
        if kind == BASE:
            return self.base(detail[0], value, path)
        if kind == NAME:
            return self.message(detail, value if value is not _MISSING else None, path)
        if kind in (ARRAY, SEQUENCE):
            (sub_kind, sub_detail), size = detail
            return self.array(sub_kind, sub_detail, size if kind == ARRAY else None, value, path)
        raise _fail(path, "a supported field type", value)

    def base(self, typ: str, value: Any, path: str) -> Any:
        if value is _MISSING:
            if typ in ("float32", "float64"):
                return 0.0
            return "" if typ == "string" else (False if typ == "bool" else 0)
        if typ == "string":
            if not isinstance(value, str):
                raise _fail(path, "a string", value)
            return value
        if typ == "bool":
            if isinstance(value, bool) or value in (0, 1):
                return bool(value)
            raise _fail(path, "a bool", value)
        if typ in _INT_RANGES:
            if isinstance(value, bool) or not isinstance(value, int):
                raise _fail(path, typ, value)
            lo, hi = _INT_RANGES[typ]
            if not lo <= value <= hi:
                raise _misfit(path, value, typ, f"{lo} to {hi}")
            return value
        if typ in ("float32", "float64"):
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise _fail(path, typ, value)
            # NaN and infinities are floats too (LaserScan ranges use them); a finite value
            # must round to a finite one, as the wire format packs it.
            try:
                number = float(value)
                if typ == "float32":
                    struct.pack("<f", number)
            except OverflowError:
                raise _misfit(path, value, typ, _FLOAT_LIMITS[typ]) from None
            return number
        raise _fail(path, f"a value of type {typ}", value)

    def array(self, kind: int, detail: Any, size: int | None, value: Any, path: str) -> Any:
        if value is _MISSING or value is None:
            value = []
            if size is not None:
                value = [_MISSING] * size
        if kind == BASE and detail[0] in ("uint8", "byte", "char") and isinstance(value, bytes):
            signed = detail[0] == "byte"
            value = [v - 256 if signed and v > 127 else v for v in value]
        if not isinstance(value, list | tuple | np.ndarray):
            raise _fail(path, "a list", value)
        if size is not None and len(value) != size:
            raise _fail(path, f"a list of exactly {size} values", value)
        items = [self.field(kind, detail, v, f"{path}[{i}]") for i, v in enumerate(value)]
        if kind == BASE and detail[0] in NUMPY_DTYPES:
            return np.array(items, dtype=NUMPY_DTYPES[detail[0]])
        return items


class _Missing:
    def __repr__(self) -> str:
        return "<missing>"


_MISSING: Final = _Missing()


def message_from_data(
    type_name: str,
    data: Any,
    *,
    clock: Clock | None = None,
    seq: int = 0,
    registry: TypeRegistry | None = None,
) -> Any:
    """A message from a mapping, a positional list, ``None``/``{}`` (all defaults)."""
    reg = registry or types()
    return _Builder(reg, clock, seq).message(reg.resolve(type_name), data, "")


def default_message(type_name: str, *, registry: TypeRegistry | None = None) -> Any:
    return message_from_data(type_name, None, registry=registry)


def message_from_args(
    type_name: str,
    args: Sequence[str],
    *,
    clock: Clock | None = None,
    seq: int = 0,
    registry: TypeRegistry | None = None,
) -> Any:
    """A message from ``rostopic pub`` arguments: one YAML mapping, or one YAML value per
    field in order (``'[0.2, 0, 0]' '[0, 0, 0.5]'`` for a Twist)."""
    values = []
    for arg in args:
        try:
            values.append(yaml.load(arg, Loader=Loader))  # a SafeLoader
        except yaml.YAMLError as err:
            mark = getattr(err, "problem_mark", None)
            where = f" at column {mark.column + 1}" if mark is not None else ""
            shown = repr(arg if len(arg) <= 60 else arg[:50] + "…")
            msg = f"argument {shown} is not valid YAML{where}: {getattr(err, 'problem', err)}"
            raise MessageValueError(msg) from None
    if not values:
        data: Any = None
    elif (len(values) == 1 and (isinstance(values[0], dict) or values[0] is None)) or (
        len(values) == 1 and values[0] in ("auto", "now")
    ):
        data = values[0]
    else:
        data = values
    return message_from_data(type_name, data, clock=clock, seq=seq, registry=registry)


# --- output --------------------------------------------------------------------------------


def message_to_data(msg: Any, *, registry: TypeRegistry | None = None) -> Any:
    """Plain Python data (dicts, lists, numbers, strings) for a message."""
    reg = registry or types()

    def convert(value: Any) -> Any:
        if hasattr(value, "__msgtype__"):
            fields = reg.store.fielddefs[value.__msgtype__][1]
            return {
                name: convert(getattr(value, name)) for name, _ in fields if name != PLACEHOLDER
            }
        if isinstance(value, np.ndarray):
            return value.tolist()
        if isinstance(value, list):
            return [convert(v) for v in value]
        return value

    return convert(msg)


def _scalar(value: Any) -> str:
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, float | np.floating):
        return repr(float(value))
    if isinstance(value, bool | np.bool_):
        return str(bool(value))
    if isinstance(value, np.integer):
        return str(int(value))
    return str(value)


def message_to_yaml(msg: Any, *, noarr: bool = False, registry: TypeRegistry | None = None) -> str:
    """The message as ``rostopic echo`` prints it (without the ``---`` separator)."""
    reg = registry or types()
    lines: list[str] = []

    def emit(value: Any, indent: str) -> None:
        name = value.__msgtype__
        if name in _TIME:
            lines.append(f"{indent}secs: {value.sec}")
            lines.append(f"{indent}nsecs: {value.nanosec}")
            return
        fields: list[tuple[str, tuple[int, Any]]] = reg.store.fielddefs[name][1]  # type: ignore[assignment]
        for fname, (kind, detail) in fields:
            if fname == PLACEHOLDER:
                continue  # a message without fields (std_srvs/Empty's): ROS 1 shows nothing
            field_value = getattr(value, fname)
            if kind == NAME:
                lines.append(f"{indent}{fname}: ")
                emit(field_value, indent + "  ")
            elif kind in (ARRAY, SEQUENCE):
                (sub_kind, sub_detail), _ = detail
                items = list(field_value)
                if noarr:
                    typ = str(sub_detail[0]) if sub_kind == BASE else short(str(sub_detail))
                    lines.append(f'{indent}{fname}: "<array type: {typ}, length: {len(items)}>"')
                elif sub_kind == NAME and items:
                    lines.append(f"{indent}{fname}: ")
                    for item in items:
                        lines.append(f"{indent}  - ")
                        emit(item, indent + "    ")
                else:
                    lines.append(f"{indent}{fname}: [{', '.join(_scalar(v) for v in items)}]")
            else:
                lines.append(f"{indent}{fname}: {_scalar(field_value)}")

    emit(msg, "")
    return "\n".join(lines)
