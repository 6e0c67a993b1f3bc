"""The kinematic engine: ArbotiX's ``arbotix_driver`` in fake mode (``sim: true``).

A differential base (``diff_controller``) that moves exactly as ``cmd_vel`` says, servo
``joints`` that move to commanded positions at their maximum speed, and ``follow_controller``
trajectories — the ROS course's "ArbotiX + rviz" step, with no physics.
"""

from belvedere.sim.kinematic._config import (
    ArbotixConfig,
    ArbotixConfigError,
    DiffControllerConfig,
    FollowControllerConfig,
    ServoConfig,
    param_locator,
)
from belvedere.sim.kinematic._diff import DiffController
from belvedere.sim.kinematic._driver import ArbotixDriver
from belvedere.sim.kinematic._follow import FollowController
from belvedere.sim.kinematic._servos import Servo
from belvedere.sim.kinematic._simulation import (
    DriverControls,
    KinematicSimulation,
    default_config,
)

__all__ = [
    "ArbotixConfig",
    "ArbotixConfigError",
    "ArbotixDriver",
    "DiffController",
    "DiffControllerConfig",
    "DriverControls",
    "FollowController",
    "FollowControllerConfig",
    "KinematicSimulation",
    "Servo",
    "ServoConfig",
    "default_config",
    "param_locator",
]
