"""ROS message types (rosbags' ROS 1 Noetic store and the standard types it lacks), and
conversion from/to the YAML that ``rostopic pub`` takes and ``rostopic echo`` prints."""

from belvedere.msgs._convert import (
    MessageValueError,
    default_message,
    message_from_args,
    message_from_data,
    message_to_data,
    message_to_yaml,
)
from belvedere.msgs._types import MessageTypeError, TypeRegistry, canonical, short, types

__all__ = [
    "MessageTypeError",
    "MessageValueError",
    "TypeRegistry",
    "canonical",
    "default_message",
    "message_from_args",
    "message_from_data",
    "message_to_data",
    "message_to_yaml",
    "short",
    "types",
]
