"""ROS 1 message classes as genpy generates them, made from belvedere's type store, for rospy
scripts: ``from geometry_msgs.msg import Twist`` after :func:`install`.

Every message type of the store has a class (:func:`message_class`) with genpy's
``__slots__``, ``_slot_types``, ``_type``, ``_md5sum``, ``_full_text``, ``_has_header``,
constructors, defaults, ``str`` and ROS 1 ``serialize``/``deserialize``; every service a class
with ``_request_class``/``_response_class`` (:func:`service_class`). :func:`to_store` and
:func:`from_store` convert between these and the store's objects, which belvedere's graph
carries. :class:`Time` and :class:`Duration` are genpy's ``time``/``duration`` values.

Not covered yet: message packages of the user's own workspace (only the store's types), and
genpy's ``serialize_numpy``/``deserialize_numpy``.
"""

from belvedere.ros1._classes import (
    Service,
    from_store,
    message_class,
    serialize_message,
    service_class,
    to_store,
)
from belvedere.ros1._finder import RosModuleFinder, install, installed, packages, uninstall
from belvedere.ros1._message import (
    DeserializationError,
    Message,
    MessageException,
    SerializationError,
    strify_message,
)
from belvedere.ros1._rostime import Duration, Time, TVal
from belvedere.ros1._show import (
    Kind,
    known_type,
    md5_text,
    package_types,
    service_args,
    show_text,
    type_names,
    type_packages,
)

__all__ = [
    "DeserializationError",
    "Duration",
    "Kind",
    "Message",
    "MessageException",
    "RosModuleFinder",
    "SerializationError",
    "Service",
    "TVal",
    "Time",
    "from_store",
    "install",
    "installed",
    "known_type",
    "md5_text",
    "message_class",
    "package_types",
    "packages",
    "serialize_message",
    "service_args",
    "service_class",
    "show_text",
    "strify_message",
    "to_store",
    "type_names",
    "type_packages",
    "uninstall",
]
