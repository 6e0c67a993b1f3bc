"""What gazebo_ros's spawn service does with ``spawn_model``'s ``-robot_namespace``: every
``<plugin>`` of the robot that names no ``<robotNamespace>`` gets one with that namespace,
in the model itself — so the plugins start in it and a saved world keeps it, as Gazebo's
rewritten SDF does. A plugin that names one keeps its own.
"""

from __future__ import annotations

from dataclasses import replace

from belvedere.description.urdf import GazeboExtension, RobotModel, Source, XmlData

__all__ = ["with_robot_namespace"]


def with_robot_namespace(model: RobotModel, namespace: str) -> RobotModel:
    """The model with ``namespace`` given to its plugins that name none ("": unchanged)."""
    if not namespace:
        return model
    return replace(model, gazebo=tuple(_extension(ext, namespace) for ext in model.gazebo))


def _extension(ext: GazeboExtension, namespace: str) -> GazeboExtension:
    plugins = tuple(replace(p, params=_params(p.params, namespace, p.source)) for p in ext.plugins)
    sensors = tuple(_walk(sensor, namespace) for sensor in ext.sensors)
    return replace(ext, plugins=plugins, sensors=sensors)


def _walk(data: XmlData, namespace: str) -> XmlData:
    """Every ``<plugin>`` inside a sensor block, at any depth (Gazebo walks the whole SDF)."""
    children = tuple(_walk(child, namespace) for child in data.children)
    if data.tag == "plugin":
        children = _params(children, namespace, data.source)
    return replace(data, children=children)


def _params(params: tuple[XmlData, ...], namespace: str, source: Source) -> tuple[XmlData, ...]:
    if any(p.tag == "robotNamespace" for p in params):
        return params
    # Located at the plugin: the namespace is the spawner's, not a line of the file, but a
    # message about it is best pointed there.
    return (*params, XmlData("robotNamespace", text=namespace, source=source))
