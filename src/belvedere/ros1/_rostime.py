"""ROS 1 ``time`` and ``duration`` values with genpy's behaviour: seconds and nanoseconds kept
canonical (``0 <= nsecs < 1e9``), arithmetic between times and durations, comparisons within a
kind, and genpy's ``str`` (nanoseconds) and ``repr`` (``genpy.Time[ns]``)."""

from __future__ import annotations

import numbers
from typing import Any, ClassVar, Self

__all__ = ["Duration", "TVal", "Time"]

_NS = 1_000_000_000


def _canonical(secs: int, nsecs: int) -> tuple[int, int]:
    carry = nsecs // _NS
    return secs + carry, nsecs - carry * _NS


class TVal:
    """What times and durations share: ``secs`` and ``nsecs``."""

    __slots__ = ("nsecs", "secs")
    _slot_types: ClassVar[list[str]] = ["int32", "int32"]
    _kind: ClassVar[str] = "genpy.TVal"

    secs: int
    nsecs: int

    def __init__(self, secs: float = 0, nsecs: int = 0) -> None:
        if isinstance(secs, numbers.Integral):
            whole, frac = int(secs), int(nsecs)
        else:
            if nsecs != 0:
                msg = "if secs is a float, nsecs cannot be set"
                raise ValueError(msg)
            whole = int(secs)
            frac = int((secs - whole) * _NS)
        self.secs, self.nsecs = _canonical(whole, frac)

    @classmethod
    def from_sec(cls, float_secs: float) -> Self:
        whole = int(float_secs)
        return cls(whole, int((float_secs - whole) * _NS))

    def is_zero(self) -> bool:
        return self.secs == 0 and self.nsecs == 0

    def set(self, secs: int, nsecs: int) -> None:
        self.secs = secs
        self.nsecs = nsecs

    def canon(self) -> None:
        self.secs, self.nsecs = _canonical(self.secs, self.nsecs)

    def to_sec(self) -> float:
        return float(self.secs) + float(self.nsecs) / 1e9

    def to_nsec(self) -> int:
        return self.secs * _NS + self.nsecs

    def __hash__(self) -> int:
        return hash((self.secs, self.nsecs))

    def __str__(self) -> str:
        return str(self.to_nsec())

    def __repr__(self) -> str:
        return f"{self._kind}[{self.to_nsec()}]"

    def __bool__(self) -> bool:
        return self.secs != 0 or self.nsecs != 0

    def __getstate__(self) -> list[int]:
        return [self.secs, self.nsecs]

    def __setstate__(self, state: list[int]) -> None:
        self.secs, self.nsecs = state

    # Ordering: only within one kind (a Time against a Time, a Duration against a Duration).
    def _compare(self, other: object) -> int:
        if not isinstance(other, self._peer()):
            msg = f"cannot compare {type(self).__name__} to {type(other).__name__}"
            raise TypeError(msg)
        a, b = self.to_nsec(), other.to_nsec()
        return (a > b) - (a < b)

    def _peer(self) -> type[TVal]:
        return TVal

    def __lt__(self, other: object) -> bool:
        try:
            return self._compare(other) < 0
        except TypeError:
            return NotImplemented

    def __le__(self, other: object) -> bool:
        try:
            return self._compare(other) <= 0
        except TypeError:
            return NotImplemented

    def __gt__(self, other: object) -> bool:
        try:
            return self._compare(other) > 0
        except TypeError:
            return NotImplemented

    def __ge__(self, other: object) -> bool:
        try:
            return self._compare(other) >= 0
        except TypeError:
            return NotImplemented

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, self._peer()):
            return False
        return self.secs == other.secs and self.nsecs == other.nsecs

    def __ne__(self, other: object) -> bool:
        return not self == other


class Time(TVal):
    """A point in time (never negative), as ROS 1's ``time`` field type."""

    __slots__ = ()
    _kind = "genpy.Time"

    def __init__(self, secs: float = 0, nsecs: int = 0) -> None:
        super().__init__(secs, nsecs)
        if self.secs < 0:
            msg = "time values must be positive"
            raise TypeError(msg)

    def _peer(self) -> type[TVal]:
        return Time

    def to_time(self) -> float:
        return self.to_sec()

    def __hash__(self) -> int:
        return hash((self.secs, self.nsecs))

    def __add__(self, other: object) -> Time:
        if not isinstance(other, Duration):
            return NotImplemented
        return type(self)(self.secs + other.secs, self.nsecs + other.nsecs)

    __radd__ = __add__

    def __sub__(self, other: object) -> Any:
        if isinstance(other, Time):
            return Duration(self.secs - other.secs, self.nsecs - other.nsecs)
        if isinstance(other, Duration):
            return type(self)(self.secs - other.secs, self.nsecs - other.nsecs)
        return NotImplemented


class Duration(TVal):
    """A span of time (may be negative), as ROS 1's ``duration`` field type."""

    __slots__ = ()
    _kind = "genpy.Duration"

    def _peer(self) -> type[TVal]:
        return Duration

    def __hash__(self) -> int:
        return hash((self.secs, self.nsecs))

    def __neg__(self) -> Duration:
        return type(self)(-self.secs, -self.nsecs)

    def __abs__(self) -> Duration:
        return self if self.secs >= 0 else -self

    def __add__(self, other: object) -> Duration:
        if not isinstance(other, Duration):
            return NotImplemented
        return type(self)(self.secs + other.secs, self.nsecs + other.nsecs)

    __radd__ = __add__

    def __sub__(self, other: object) -> Duration:
        if not isinstance(other, Duration):
            return NotImplemented
        return type(self)(self.secs - other.secs, self.nsecs - other.nsecs)

    def __mul__(self, factor: object) -> Duration:
        if isinstance(factor, numbers.Integral):
            n = int(factor)
            return type(self)(self.secs * n, self.nsecs * n)
        if isinstance(factor, numbers.Real):
            return type(self).from_sec(self.to_sec() * float(factor))
        return NotImplemented

    __rmul__ = __mul__

    def __floordiv__(self, divisor: object) -> Any:
        if isinstance(divisor, numbers.Real):
            return type(self).from_sec(self.to_sec() // float(divisor))
        if isinstance(divisor, Duration):
            return int(self.to_sec() // divisor.to_sec())
        return NotImplemented

    def __truediv__(self, divisor: object) -> Any:
        if isinstance(divisor, numbers.Real):
            return type(self).from_sec(self.to_sec() / float(divisor))
        if isinstance(divisor, Duration):
            return self.to_sec() / divisor.to_sec()
        return NotImplemented

    def __mod__(self, other: object) -> Duration:
        if not isinstance(other, Duration):
            return NotImplemented
        return type(self).from_sec(self.to_sec() % other.to_sec())

    def __divmod__(self, other: object) -> tuple[int, Duration]:
        if not isinstance(other, Duration):
            return NotImplemented
        quotient, remainder = divmod(self.to_sec(), other.to_sec())
        return int(quotient), type(self).from_sec(remainder)
