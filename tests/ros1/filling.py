"""Messages with every field set, deterministically, for the differential and round-trip
tests."""

from __future__ import annotations

import random
from typing import Any, Final

from belvedere.ros1 import Duration, Message, Time, message_class
from belvedere.ros1._spec import FieldSpec, message_spec

INT_RANGES: Final = {
    "byte": (-128, 127),
    "int8": (-128, 127),
    "char": (0, 255),
    "uint8": (0, 255),
    "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1),
    "uint64": (0, 2**64 - 1),
}
"""ROS 1's integer types' bounds, stated here rather than taken from belvedere's own table, so
that a wrong bound there shows."""
FLOATS: Final = (0.1, -2.5, 1e-20, 123456.789, 3.0, -0.0, 1.5e300)
FLOAT32S: Final = (0.5, -2.5, 1024.0, 3.0, -0.0)
STRINGS: Final = ("", "a b", "it's", 'say "hi"', "yes", "1", "x: y", "- dash", "tab\there", "é")


def filled(name: str, seed: int = 0) -> Message:
    """A message of type ``name`` (store name) with every field given a value."""
    return _message(name, random.Random(seed))


def _message(name: str, rng: random.Random) -> Message:
    spec = message_spec(name)
    cls = message_class(name)
    return cls(**{f.name: _field(f, rng) for f in spec.fields})


def _field(field: FieldSpec, rng: random.Random) -> Any:
    if field.array is None:
        return _single(field, rng)
    n = field.array or rng.randint(0, 3)
    if field.base in ("uint8", "char"):
        return bytes(rng.randint(0, 255) for _ in range(n))
    return [_single(field, rng) for _ in range(n)]


def _single(field: FieldSpec, rng: random.Random) -> Any:
    base = field.base
    if field.is_message:
        return _message(base, rng)
    if base == "time":
        return Time(rng.randint(0, 2**31), rng.randint(0, 999_999_999))
    if base == "duration":
        return Duration(rng.randint(-(2**30), 2**30), rng.randint(0, 999_999_999))
    if base in INT_RANGES:
        low, high = INT_RANGES[base]
        return rng.choice((low, high, 0, rng.randint(low, high)))
    if base == "float64":
        return rng.choice(FLOATS)
    if base == "float32":
        return rng.choice(FLOAT32S)
    if base == "bool":
        return rng.choice((True, False))
    if base == "string":
        return rng.choice(STRINGS)
    msg = f"no value for {base!r}"
    raise AssertionError(msg)
