"""``libgazebo_ros_control.so`` and the controller_manager, as gazebo_ros_control's
DefaultRobotHWSim and ros_controllers behave.

Transmissions give each joint one command interface (effort, velocity or position). Without
PID gains (``<ns>/gazebo_ros_control/pid_gains/<joint>``) a velocity joint is driven like
Gazebo's joint motor and a position joint like a stiff servo, both within the URDF effort
limit; with gains, a PID computes the effort. Controllers are loaded from the parameter tree
(``<ns>/<controller>/type``) by the ``load_controller``/``switch_controller`` services — what
``controller_manager spawner`` calls — and run every ``controlPeriod``.

The hardware interface's joints (:mod:`._hardware`), the controllers (:mod:`._controllers`,
:mod:`._diff_drive`), the controller manager and its spawner (:mod:`._manager`), and the
Gazebo plugin that holds them (:mod:`._robot_hw`).
"""

from belvedere.sim.physics._ros_control._manager import CONTROLLER_TYPES, spawner
from belvedere.sim.physics._ros_control._robot_hw import RosControl

__all__ = ["CONTROLLER_TYPES", "RosControl", "spawner"]
