"""The robot model: ``RobotModel`` parsed from URDF or xacro, with urdfdom's verdicts.

Everything downstream (checks, viewer, simulators, launch) reads the robot through this
model. Every part remembers its source (:class:`Source`): its URDF line and, when the URDF
came from xacro, the xacro line that produced it.
"""

from belvedere.description.urdf._model import (
    Actuator,
    Box,
    Calibration,
    Collision,
    Cylinder,
    Dynamics,
    GazeboExtension,
    GazeboPlugin,
    Geometry,
    Inertial,
    Joint,
    JointType,
    Limit,
    Link,
    Material,
    Mesh,
    Mimic,
    Pose,
    SafetyController,
    Source,
    Sphere,
    Transmission,
    TransmissionJoint,
    Vec3,
    Visual,
    XmlData,
)
from belvedere.description.urdf._parse import Diagnostic, ParsedRobot, parse_robot
from belvedere.description.urdf._robot import (
    RobotModel,
    URDFError,
    load_robot,
    rpy_to_matrix,
    transform,
)
from belvedere.description.urdf._write import xml_element

__all__ = [
    "Actuator",
    "Box",
    "Calibration",
    "Collision",
    "Cylinder",
    "Diagnostic",
    "Dynamics",
    "GazeboExtension",
    "GazeboPlugin",
    "Geometry",
    "Inertial",
    "Joint",
    "JointType",
    "Limit",
    "Link",
    "Material",
    "Mesh",
    "Mimic",
    "ParsedRobot",
    "Pose",
    "RobotModel",
    "SafetyController",
    "Source",
    "Sphere",
    "Transmission",
    "TransmissionJoint",
    "URDFError",
    "Vec3",
    "Visual",
    "XmlData",
    "load_robot",
    "parse_robot",
    "rpy_to_matrix",
    "transform",
    "xml_element",
]
