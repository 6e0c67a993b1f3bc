"""``dynamic_reconfigure.server.Server`` for rospy scripts: a node's reconfigurable
parameters, as ROS's Python server keeps them.

The server reads its starting values from the parameter server (``~name``), clamps them to
their ranges, calls the callback with level ``~0`` (-1) and serves ``~set_parameters``
(``dynamic_reconfigure/Reconfigure``); it latches ``~parameter_descriptions`` and, after every
change, ``~parameter_updates``, and writes the values back to the parameter server. A change's
level is the OR of the levels of the parameters whose values changed; the callback's return
value is the new configuration. Unlike ROS, a value of the wrong type or outside an enum is
refused (the service call fails naming it) instead of reaching the callback.
"""

from __future__ import annotations

import copy
import threading
from collections.abc import Callable, Mapping
from typing import Any

from belvedere.ros1._classes import message_class, service_class
from belvedere.ros1.dynamic_reconfigure._description import (
    Description,
    ReconfigureError,
    config_values,
)
from belvedere.ros1.dynamic_reconfigure._encoding import (
    Config,
    config_message,
    description_message,
    group_tree,
    message_data,
)
from belvedere.ros1.dynamic_reconfigure._exceptions import DynamicReconfigureCallbackException
from belvedere.ros1.rospy import (
    Publisher,
    Service,
    ServiceException,
    get_param,
    logerr,
    logwarn,
    set_param,
)

__all__ = ["Server", "describe"]

Callback = Callable[[Config, int], Any]


def describe(config_type: Any) -> Description:
    """The description of a ``<Name>Config`` module (or of a :class:`Description`)."""
    if isinstance(config_type, Description):
        return config_type
    found = getattr(config_type, "description", None)
    if not isinstance(found, Description):
        msg = f"{config_type!r} is not a <Name>Config module generated from a .cfg"
        raise TypeError(msg)
    return found


def _namespace(namespace: str) -> str:
    if not namespace or namespace == "~":
        return "~"
    if namespace[0] not in "/~":
        namespace = "~" + namespace
    return (namespace + "/").replace("//", "/")


class Server:
    """A node's reconfigurable parameters (``type``: the generated ``<Name>Config``)."""

    def __init__(self, type: Any, callback: Callback, namespace: str = "") -> None:
        self.mutex = threading.Lock()
        self.ns = _namespace(namespace)
        self.type = type
        self.description = describe(type)
        self.callback = callback
        self.config: Config = Config(self.description.defaults)
        for p in self.description.params():
            stored = get_param(self.ns + p.name, None)
            if stored is None:
                continue
            try:
                self.config[p.name] = p.accept(stored)
            except ReconfigureError as err:
                logwarn("%s: keeping its default %r", err.message, p.default)
        descr_class = message_class("dynamic_reconfigure/msg/ConfigDescription")
        self.descr_topic = Publisher(
            self.ns + "parameter_descriptions", descr_class, latch=True, queue_size=10
        )
        self.descr_topic.publish(description_message(self.description))
        self.update_topic = Publisher(
            self.ns + "parameter_updates",
            message_class("dynamic_reconfigure/msg/Config"),
            latch=True,
            queue_size=10,
        )
        with self.mutex:
            self._change_config(dict(self.config), ~0)
        self.set_service = Service(
            self.ns + "set_parameters",
            service_class("dynamic_reconfigure/Reconfigure"),
            self._set_callback,
        )

    def update_configuration(self, changes: Mapping[str, Any]) -> Config:
        """Apply ``changes`` (clamped, type-checked) and call the callback; the new
        configuration.

        Raises:
            ReconfigureError: an unknown parameter, a value of the wrong type, or outside
                an enum.
        """
        with self.mutex:
            plain = {k: v for k, v in changes.items() if k != "groups"}
            new = self.description.merged(self._values(), plain)
            return self._change_config(new, self.description.level(new, self._values()))

    def _values(self) -> dict[str, Any]:
        return {p.name: self.config[p.name] for p in self.description.params()}

    def _change_config(self, values: dict[str, Any], level: int) -> Config:
        offered = Config(copy.deepcopy(values))
        offered["groups"] = group_tree(self.description, values, flat=False)
        result = self.callback(offered, level)
        if result is None:
            msg = "Reconfigure callback should return a possibly updated configuration."
            logerr(msg)
            raise DynamicReconfigureCallbackException(msg)
        kept = self.description.merged(
            values, {p.name: result[p.name] for p in self.description.params() if p.name in result}
        )
        self.config = Config(kept)
        self.config["groups"] = group_tree(self.description, kept, flat=False)
        for name, value in kept.items():
            set_param(self.ns + name, value)
        self.update_topic.publish(config_message(kept, self.description))
        return self.config

    def _set_callback(self, request: Any) -> Any:
        changes = config_values(message_data(request.config))
        try:
            config = self.update_configuration(changes)
        except ReconfigureError as err:
            raise ServiceException(err.describe()) from None
        reply = service_class("dynamic_reconfigure/Reconfigure")._response_class
        return reply(config=config_message(config, self.description))
