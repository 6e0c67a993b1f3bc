"""``dynamic_reconfigure.client.Client`` for rospy scripts: another node's reconfigurable
parameters, read from its latched topics and changed through its ``set_parameters``."""

from __future__ import annotations

import ast
import sys
import threading
import time
from collections.abc import Callable, Mapping
from typing import Any

from belvedere.ros1._classes import message_class, service_class
from belvedere.ros1.dynamic_reconfigure._description import (
    TYPES,
    Description,
    Param,
    config_values,
)
from belvedere.ros1.dynamic_reconfigure._encoding import (
    Config,
    config_message,
    decode_config,
    decode_description,
    group_tree,
    message_data,
)
from belvedere.ros1.dynamic_reconfigure._exceptions import (
    DynamicReconfigureCallbackException,
    DynamicReconfigureParameterException,
)
from belvedere.ros1.rospy import (
    ROSException,
    ServiceException,
    ServiceProxy,
    Subscriber,
    is_shutdown,
    resolve_name,
    wait_for_service,
)

__all__ = ["Client"]


def _say(text: object, stream: Any = None) -> None:
    """Print as ROS's tool prints (a line on stdout, or on ``stream``)."""
    (stream or sys.stdout).write(f"{text}\n")


def _truthy(text: str) -> bool:
    return text.lower() in ("yes", "true", "t", "1")


class Client:
    """The reconfigurable parameters of node ``name``."""

    def __init__(
        self,
        name: str,
        timeout: float | None = None,
        config_callback: Callable[[Config | None], Any] | None = None,
        description_callback: Callable[[list[dict[str, Any]] | None], Any] | None = None,
    ) -> None:
        self.name = name
        self.config: Config | None = None
        self.param_description: list[dict[str, Any]] | None = None
        self.group_description: Config | None = None
        self._description: Description | None = None
        self._cv = threading.Condition()
        self._config_callback = config_callback
        self._description_callback = description_callback
        service = resolve_name(name + "/set_parameters")
        if not timeout:
            try:
                wait_for_service(service, 1.0)
            except ROSException:
                _say(f"Waiting for service {service}...", sys.stderr)
                wait_for_service(service)
        else:
            wait_for_service(service, timeout)
        self._set_service = ServiceProxy(service, service_class("dynamic_reconfigure/Reconfigure"))
        self._descriptions_sub = Subscriber(
            resolve_name(name + "/parameter_descriptions"),
            message_class("dynamic_reconfigure/msg/ConfigDescription"),
            self._descriptions_msg,
        )
        self._updates_sub = Subscriber(
            resolve_name(name + "/parameter_updates"),
            message_class("dynamic_reconfigure/msg/Config"),
            self._updates_msg,
        )

    def _wait(self, ready: Callable[[], bool], timeout: float | None) -> None:
        deadline = None if not timeout else time.monotonic() + timeout
        with self._cv:
            while not ready() and not is_shutdown():
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    return
                self._cv.wait(0.1 if left is None else min(left, 0.1))

    def get_configuration(self, timeout: float | None = None) -> Config | None:
        """The server's latest configuration (waiting for one; None after ``timeout``)."""
        if not timeout:
            self._wait(lambda: self.config is not None, 1.0)
            if self.config is None:
                _say("Waiting for configuration...", sys.stderr)
        self._wait(lambda: self.config is not None, timeout)
        return self.config

    def get_parameter_descriptions(self, timeout: float | None = None) -> Any:
        """Every parameter as a dict (name, type, level, description, default, min, max,
        edit_method), or None after ``timeout``."""
        self._wait(lambda: self.param_description is not None, timeout)
        return self.param_description

    def get_group_descriptions(self, timeout: float | None = None) -> Config | None:
        self._wait(lambda: self.group_description is not None, timeout)
        return self.group_description

    def update_configuration(self, changes: Mapping[str, Any]) -> Config:
        """Change the server's configuration; what it holds afterwards.

        Values are converted as ROS's client converts them: text to the parameter's type,
        an enum constant's name to its value, ``yes``/``true``/``1`` to True.
        """
        self.get_parameter_descriptions()
        described = self._description
        values: dict[str, Any] = {}
        for name, value in changes.items():
            if name == "groups":
                continue
            if described is None:
                values[name] = value
                continue
            values[name] = self._converted(described, name, value)
        request = service_class("dynamic_reconfigure/Reconfigure")._request_class
        config = config_message(values, None)
        try:
            reply = self._set_service(request(config=config))
        except ServiceException as err:
            msg = f"service call failed: {err}"
            raise DynamicReconfigureCallbackException(msg) from None
        return decode_config(config_values(message_data(reply.config)), described)

    @staticmethod
    def _converted(described: Description, name: str, value: Any) -> Any:
        param: Param | None = next((p for p in described.params() if p.name == name), None)
        if param is None:
            msg = f"don't know parameter: {name}"
            raise DynamicReconfigureParameterException(msg)
        want = TYPES[param.type]
        try:
            if want is bool and isinstance(value, str):
                return _truthy(value)
            if isinstance(value, str) and param.edit_method:
                enum = ast.literal_eval(param.edit_method).get("enum", [])
                for const in enum:
                    if value.lower() == str(const["name"]).lower():
                        return TYPES[const["type"]](const["value"])
            return want(value)
        except (ValueError, SyntaxError, TypeError) as err:
            msg = f"can't set parameter '{name}' of {want}: {err}"
            raise DynamicReconfigureParameterException(msg) from None

    def close(self) -> None:
        self._descriptions_sub.unregister()
        self._updates_sub.unregister()

    @property
    def config_callback(self) -> Callable[[Config | None], Any] | None:
        return self._config_callback

    @config_callback.setter
    def config_callback(self, value: Callable[[Config | None], Any] | None) -> None:
        self._config_callback = value
        if value is not None:
            value(self.config)

    @property
    def description_callback(self) -> Callable[[list[dict[str, Any]] | None], Any] | None:
        return self._description_callback

    @description_callback.setter
    def description_callback(
        self, value: Callable[[list[dict[str, Any]] | None], Any] | None
    ) -> None:
        self._description_callback = value
        if value is not None:
            value(self.param_description)

    def _updates_msg(self, msg: Any) -> None:
        self._wait(lambda: self._description is not None, 1.0)
        with self._cv:
            self.config = decode_config(config_values(message_data(msg)), self._description)
            self._cv.notify_all()
        if self._config_callback is not None:
            self._config_callback(self.config)

    def _descriptions_msg(self, msg: Any) -> None:
        described = decode_description(message_data(msg))
        with self._cv:
            self._description = described
            self.param_description = [p.as_dict() for p in described.params()]
            self.group_description = _group_description(described)
            self._cv.notify_all()
        if self._description_callback is not None:
            self._description_callback(self.param_description)


def _group_description(described: Description) -> Config:
    tree = group_tree(described, {}, flat=False)

    def fill(node: Config, group: Any) -> None:
        node["parameters"] = [p.as_dict() for p in group.params]
        for child in group.groups:
            fill(node["groups"][child.name], child)

    fill(tree, described.root)
    return tree
