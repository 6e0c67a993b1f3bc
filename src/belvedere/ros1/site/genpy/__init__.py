"""genpy's message base and time types (belvedere.ros1)."""

from belvedere.ros1 import (
    DeserializationError,
    Duration,
    Message,
    MessageException,
    SerializationError,
    Time,
    TVal,
)

__all__ = [
    "DeserializationError",
    "Duration",
    "Message",
    "MessageException",
    "SerializationError",
    "TVal",
    "Time",
]
