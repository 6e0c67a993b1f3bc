"""dynamic_reconfigure's Python values: :class:`Config` (a dict read as attributes) and the
conversions between configurations, descriptions and the messages rospy scripts handle."""

from __future__ import annotations

import ast
import copy
from collections.abc import Mapping
from typing import Any

from belvedere.msgs import message_from_data, message_to_data
from belvedere.ros1._classes import from_store, to_store
from belvedere.ros1._message import Message
from belvedere.ros1.dynamic_reconfigure._description import (
    Description,
    Group,
    Param,
    config_data,
    config_values,
)

__all__ = [
    "Config",
    "config_message",
    "decode_config",
    "decode_description",
    "description_message",
    "extract_params",
    "group_tree",
    "message_data",
]


class Config(dict[str, Any]):
    """A configuration: ``config.int_param`` is ``config["int_param"]``."""

    def __getattr__(self, name: str) -> Any:
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __setattr__(self, name: str, value: Any) -> None:
        self[name] = value

    def copy(self) -> Config:
        return Config(self)

    def __deepcopy__(self, memo: dict[int, Any]) -> Config:
        return Config({k: copy.deepcopy(v, memo) for k, v in self.items()})


def message_data(msg: Message) -> Any:
    """A rospy message as plain data."""
    return message_to_data(to_store(msg))


def config_message(values: Mapping[str, Any], description: Description | None) -> Message:
    """``dynamic_reconfigure/Config`` (a rospy message) for ``values`` (with the group
    states of ``description``, if given)."""
    plain = {k: v for k, v in values.items() if k != "groups"}
    states = description.group_states() if description is not None else []
    data = config_data(plain, states)
    return from_store(message_from_data("dynamic_reconfigure/msg/Config", data))


def description_message(description: Description) -> Message:
    """``dynamic_reconfigure/ConfigDescription`` (a rospy message) for ``description``."""
    data = description.message_data()
    return from_store(message_from_data("dynamic_reconfigure/msg/ConfigDescription", data))


def _group_dict(group: Group | Mapping[str, Any]) -> Config:
    get = (lambda k: getattr(group, k)) if isinstance(group, Group) else group.get
    return Config(
        id=get("id"),
        parent=get("parent"),
        name=get("name"),
        type=get("type") or "",
        state=get("state") if get("state") is not None else True,
        groups=Config(),
        parameters=Config(),
    )


def group_tree(description: Description, values: Mapping[str, Any], *, flat: bool) -> Config:
    """The ``groups`` entry of a configuration: the group tree with each group's values —
    under ``parameters`` as a server's callback sees them, or beside the group's own keys
    (``flat``) as a client decodes them."""

    def build(group: Group) -> Config:
        out = _group_dict(group)
        for p in group.params:
            if p.name in values:
                if flat:
                    out[p.name] = values[p.name]
                else:
                    out["parameters"][p.name] = values[p.name]
        for child in group.groups:
            out["groups"][child.name] = build(child)
        return out

    return build(description.root)


def decode_config(values: Mapping[str, Any], description: Description | None) -> Config:
    """A client's view of a configuration: the values, then (knowing the description) the
    group tree."""
    out = Config(values)
    if description is not None:
        out["groups"] = group_tree(description, values, flat=True)
    return out


def decode_description(data: Mapping[str, Any]) -> Description:
    """A ``ConfigDescription`` (as data) back into a :class:`Description`."""
    mins, maxes = config_values(data["min"]), config_values(data["max"])
    dflts = config_values(data["dflt"])
    groups: dict[int, Group] = {}
    for g in data["groups"]:
        params = [
            Param(
                p["name"],
                p["type"],
                p["level"],
                p["description"],
                dflts.get(p["name"]),
                mins.get(p["name"]),
                maxes.get(p["name"]),
                p["edit_method"],
            )
            for p in g["parameters"]
        ]
        groups[g["id"]] = Group(g["name"], g["type"], True, g["id"], g["parent"], params)
    for ident, group in groups.items():
        if ident != 0 and group.parent in groups:
            groups[group.parent].groups.append(group)
    root = groups.get(0, Group("Default"))
    constants: dict[str, Any] = {}
    for p in [p for g in groups.values() for p in g.params]:
        if p.edit_method:
            try:
                enum = ast.literal_eval(p.edit_method).get("enum", [])
                constants.update({c["name"]: c["value"] for c in enum})
            except (ValueError, SyntaxError, AttributeError, TypeError, KeyError):
                pass
    return Description("", root, constants)


def extract_params(group: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Every parameter of a ``config_description`` group and its subgroups, depth first."""
    params = list(group["parameters"])
    children = group["groups"]
    for child in children.values() if isinstance(children, Mapping) else children:
        params.extend(extract_params(child))
    return params
