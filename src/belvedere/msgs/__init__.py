"""ROS message types (rosbags' ROS 1 Noetic store and the standard types it lacks), and
conversion from/to the YAML that ``rostopic pub`` takes and ``rostopic echo`` prints;
``build`` has fast constructors for the messages simulations publish at high rates."""

from belvedere.msgs import _build as build
from belvedere.msgs._convert import (
    NUMPY_DTYPES,
    MessageValueError,
    default_message,
    message_from_args,
    message_from_data,
    message_to_data,
    message_to_yaml,
)
from belvedere.msgs._fulltext import (
    DefinitionError,
    FullText,
    learn_full_text,
    learn_service_text,
    read_full_text,
)
from belvedere.msgs._genmsg import InterfaceError
from belvedere.msgs._ros1text import Ros1Text, ros1_name, ros1_text
from belvedere.msgs._types import (
    PLACEHOLDER,
    MessageTypeError,
    TypeRegistry,
    canonical,
    short,
    types,
)

__all__ = [
    "NUMPY_DTYPES",
    "PLACEHOLDER",
    "DefinitionError",
    "FullText",
    "InterfaceError",
    "MessageTypeError",
    "MessageValueError",
    "Ros1Text",
    "TypeRegistry",
    "build",
    "canonical",
    "default_message",
    "learn_full_text",
    "learn_service_text",
    "message_from_args",
    "message_from_data",
    "message_to_data",
    "message_to_yaml",
    "read_full_text",
    "ros1_name",
    "ros1_text",
    "short",
    "types",
]
