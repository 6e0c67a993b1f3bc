"""The physics engine: MuJoCo, with the model built by us from the robot and world models,
and Gazebo's ROS plugins (diff drive, sensors, ros_control) read from ``<gazebo>`` tags."""

import os

# Cameras render offscreen; without a display, Mesa's EGL (llvmpipe) is the way.
os.environ.setdefault("MUJOCO_GL", "egl")

from belvedere.sim.physics._builder import RobotBuild, add_robot
from belvedere.sim.physics._cameras import CameraSensor, DepthCamera
from belvedere.sim.physics._engine import Engine
from belvedere.sim.physics._gazebo_ros import (
    SAVE_WORLD,
    SAVE_WORLD_TYPE,
    GazeboRos,
    name_taken,
    parse_spawn_args,
    spawn_model,
)
from belvedere.sim.physics._ros_control import CONTROLLER_TYPES, RosControl, spawner
from belvedere.sim.physics._save import WorldSnapshot, save_world, snapshot
from belvedere.sim.physics._sensors import ImuSensor, LaserSensor
from belvedere.sim.physics._simulation import PLUGINS, PhysicsSimulation, SpawnedRobot
from belvedere.sim.physics._spec import ModelError, new_spec
from belvedere.sim.physics._world_build import add_world

__all__ = [
    "CONTROLLER_TYPES",
    "PLUGINS",
    "SAVE_WORLD",
    "SAVE_WORLD_TYPE",
    "CameraSensor",
    "DepthCamera",
    "Engine",
    "GazeboRos",
    "ImuSensor",
    "LaserSensor",
    "ModelError",
    "PhysicsSimulation",
    "RobotBuild",
    "RosControl",
    "SpawnedRobot",
    "WorldSnapshot",
    "add_robot",
    "add_world",
    "name_taken",
    "new_spec",
    "parse_spawn_args",
    "save_world",
    "snapshot",
    "spawn_model",
    "spawner",
]
