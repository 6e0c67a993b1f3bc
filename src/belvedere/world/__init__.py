"""Worlds: ``WorldModel`` read from Gazebo ``.world`` files and ``model://`` models, and
written back as SDF 1.6 (a simulation's current world, saved).

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
from belvedere.world._urdf import MeshPath, robot_entry
from belvedere.world._writer import WorldState, world_sdf, write_world

__all__ = [
    "BUILTIN_MODELS",
    "Attenuation",
    "Light",
    "Material",
    "MeshPath",
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
    "WorldState",
    "empty_world",
    "model_sdf_file",
    "read_world",
    "read_world_string",
    "robot_entry",
    "world_sdf",
    "write_world",
]
