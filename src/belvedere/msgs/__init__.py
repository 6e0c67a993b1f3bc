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
from belvedere.msgs._fieldpath import (
    FieldPathError,
    Series,
    field_value,
    resolve_series,
    split_plot_args,
)
from belvedere.msgs._fulltext import (
    DefinitionError,
    FullText,
    learn_full_text,
    learn_service_text,
    read_full_text,
)
from belvedere.msgs._gamepad import (
    GAMEPAD_TOPIC,
    GAMEPAD_TYPE,
    GamepadState,
    gamepad_from_json,
    gamepad_from_msg,
    gamepad_state,
)
from belvedere.msgs._genmsg import InterfaceError
from belvedere.msgs._images import (
    IMAGE_ENCODINGS,
    ImageError,
    compressed_rgb,
    depth_rgb,
    image_rgb,
)
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
    "GAMEPAD_TOPIC",
    "GAMEPAD_TYPE",
    "IMAGE_ENCODINGS",
    "NUMPY_DTYPES",
    "PLACEHOLDER",
    "DefinitionError",
    "FieldPathError",
    "FullText",
    "GamepadState",
    "ImageError",
    "InterfaceError",
    "MessageTypeError",
    "MessageValueError",
    "Ros1Text",
    "Series",
    "TypeRegistry",
    "build",
    "canonical",
    "compressed_rgb",
    "default_message",
    "depth_rgb",
    "field_value",
    "gamepad_from_json",
    "gamepad_from_msg",
    "gamepad_state",
    "image_rgb",
    "learn_full_text",
    "learn_service_text",
    "message_from_args",
    "message_from_data",
    "message_to_data",
    "message_to_yaml",
    "read_full_text",
    "resolve_series",
    "ros1_name",
    "ros1_text",
    "short",
    "split_plot_args",
    "types",
]
