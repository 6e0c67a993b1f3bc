"""Worlds: ``WorldModel`` read from Gazebo ``.world`` files and ``model://`` models.

Models are found as Gazebo finds them (``GAZEBO_MODEL_PATH``, ``~/.gazebo/models``, ROS
packages' exported model paths), never downloaded; a missing one is an error naming it, the
line that asked for it and every directory searched.
"""

from belvedere.world._model import (
    Attenuation,
    Light,
    Material,
    Physics,
    Plane,
    Polyline,
    Scene,
    Shape,
    Surface,
    WorldFrame,
    WorldGeometry,
    WorldJoint,
    WorldLink,
    WorldModel,
    WorldModelEntry,
)
from belvedere.world._paths import BUILTIN_MODELS, ModelPaths, model_sdf_file
from belvedere.world._sdf import (
    SDFError,
    empty_world,
    read_world,
    read_world_string,
)

__all__ = [
    "BUILTIN_MODELS",
    "Attenuation",
    "Light",
    "Material",
    "ModelPaths",
    "Physics",
    "Plane",
    "Polyline",
    "SDFError",
    "Scene",
    "Shape",
    "Surface",
    "WorldFrame",
    "WorldGeometry",
    "WorldJoint",
    "WorldLink",
    "WorldModel",
    "WorldModelEntry",
    "empty_world",
    "model_sdf_file",
    "read_world",
    "read_world_string",
]
