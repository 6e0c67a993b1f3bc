"""Worlds: ``WorldModel`` read from Gazebo ``.world`` files and ``model://`` models, and
written back as SDF 1.6 (a simulation's current world, saved).

Models are found as Gazebo finds them (``GAZEBO_MODEL_PATH``, ``~/.gazebo/models``, ROS
packages' exported model paths), never downloaded; a missing one is an error naming it, the
line that asked for it and every directory searched.
"""

from belvedere.world._building import (
    DOOR,
    WINDOW,
    Building,
    BuildingError,
    Opening,
    Piece,
    Wall,
    building_config,
    building_sdf,
    opening_at,
    snap,
    write_building,
)
from belvedere.world._library import (
    SHAPES,
    LibraryError,
    LibraryModel,
    load_model,
    model_library,
    simple_shape,
)
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
from belvedere.world._robot import saved_robot
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
    "DOOR",
    "SHAPES",
    "WINDOW",
    "Attenuation",
    "Building",
    "BuildingError",
    "LibraryError",
    "LibraryModel",
    "Light",
    "Material",
    "MeshPath",
    "ModelPaths",
    "Opening",
    "Physics",
    "Piece",
    "Plane",
    "Polyline",
    "SDFError",
    "Scene",
    "Shape",
    "Surface",
    "Wall",
    "WorldFrame",
    "WorldGeometry",
    "WorldJoint",
    "WorldLink",
    "WorldModel",
    "WorldModelEntry",
    "WorldState",
    "building_config",
    "building_sdf",
    "empty_world",
    "load_model",
    "model_library",
    "model_sdf_file",
    "opening_at",
    "read_world",
    "read_world_string",
    "robot_entry",
    "saved_robot",
    "simple_shape",
    "snap",
    "world_sdf",
    "write_building",
    "write_world",
]
