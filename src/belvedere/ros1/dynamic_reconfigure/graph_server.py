"""dynamic_reconfigure's server for belvedere's own nodes (amcl, move_base, its planners):
the same topics, service and rules as :class:`.server.Server`, on a graph node, called on the
graph's executor (no thread of its own, so a simulated run stays deterministic).

The node hands over its current values (what it runs with, which may differ from the
description's defaults) and ``apply``, which takes a whole new configuration and the level
of what changed, and returns the configuration it runs with (its own corrections), or raises
``ValueError`` to refuse it (the service call fails, nothing changes).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from belvedere.graph import Node, ServiceFailedError
from belvedere.msgs import message_from_data, message_to_data
from belvedere.ros1.dynamic_reconfigure._description import (
    Description,
    ReconfigureError,
    config_data,
    config_values,
)

__all__ = ["GraphServer"]

Apply = Callable[[dict[str, Any], int], Mapping[str, Any] | None]


class GraphServer:
    """``<ns>/set_parameters``, ``<ns>/parameter_descriptions`` and
    ``<ns>/parameter_updates`` for ``description`` (``ns``: ``~`` or ``~<planner>``)."""

    def __init__(
        self,
        node: Node,
        description: Description,
        current: Mapping[str, Any],
        apply: Apply,
        *,
        ns: str = "~",
    ) -> None:
        self.node = node
        self.description = description
        self.apply = apply
        self.ns = ns if ns.endswith("/") else ns + "/"
        self.config: dict[str, Any] = {
            p.name: p.accept(current[p.name]) if p.name in current else p.default
            for p in description.params()
        }
        described = message_from_data(
            "dynamic_reconfigure/msg/ConfigDescription", description.message_data()
        )
        descriptions = node.publisher(
            self.ns + "parameter_descriptions", described.__msgtype__, latch=True
        )
        descriptions.publish(described)
        self.updates = node.publisher(
            self.ns + "parameter_updates", "dynamic_reconfigure/msg/Config", latch=True
        )
        self._publish()
        node.service(self.ns + "set_parameters", "dynamic_reconfigure/Reconfigure", self._set)

    def _publish(self) -> None:
        data = config_data(self.config, self.description.group_states())
        self.updates.publish(message_from_data("dynamic_reconfigure/msg/Config", data))

    def update(self, changes: Mapping[str, Any]) -> dict[str, Any]:
        """Apply ``changes`` as a ``set_parameters`` call does; the configuration after.

        Raises:
            ReconfigureError: an unknown parameter, the wrong type, outside an enum, or a
                configuration the node refuses.
        """
        new = self.description.merged(self.config, changes)
        level = self.description.level(new, self.config)
        try:
            kept = self.apply(dict(new), level)
        except ValueError as err:
            msg = f"{self.node.full_name} refuses the configuration: {err}"
            raise ReconfigureError(msg) from None
        if kept is not None:
            new = self.description.merged(new, {k: v for k, v in kept.items() if k in new})
        self.config = new
        for name, value in new.items():
            self.node.set_param(self.ns + name, value)
        self._publish()
        return new

    def _set(self, request: Any) -> Any:
        changes = config_values(message_to_data(request.config))
        try:
            config = self.update(changes)
        except ReconfigureError as err:
            name = self.node.resolve(self.ns + "set_parameters")
            raise ServiceFailedError(name, err.message) from None
        data = {"config": config_data(config, self.description.group_states())}
        return message_from_data("dynamic_reconfigure/srv/Reconfigure_Response", data)
