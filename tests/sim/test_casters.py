"""Caster balls welded to their carrier where the joint changes nothing: the course's mbot
loses its two caster DOFs, drives exactly as with them (MuJoCo, 4 s of driving), and a caster
joint that matters (named by a plugin, damped, with friction, off-centre) stays a joint."""

from __future__ import annotations

import mujoco
import numpy as np
import numpy.typing as npt
import pytest

from belvedere.description.urdf import RobotModel
from belvedere.packages import PackageIndex
from belvedere.sim.physics._builder import add_robot
from belvedere.sim.physics._spec import new_spec
from belvedere.sim.physics._world_build import add_world
from belvedere.world import empty_world
from tests.conftest import EXAMPLES

MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"


def _drive(
    model: RobotModel, *, weld: bool
) -> tuple[npt.NDArray[np.float64], int, tuple[str, ...]]:
    """The base's pose every 0.5 s over 4 s of two wheel-speed commands, the model's DOFs and
    the welded joints. Hinged, the caster joints lose the builder's small armature (a
    numerical help, not part of the URDF) so that both models stand for the same robot."""
    world = empty_world()
    spec = new_spec(world.physics)
    add_world(spec, world)
    build = add_robot(
        spec, model, name="mbot", packages=PackageIndex([EXAMPLES]), weld_casters=weld
    )
    for joint in spec.joints:
        if "caster" in joint.name:
            joint.armature = 0.0
    for side in ("left_wheel_joint", "right_wheel_joint"):
        actuator = spec.add_actuator(
            name=side, target=build.joints[side], trntype=mujoco.mjtTrn.mjTRN_JOINT
        )
        actuator.set_to_velocity(kv=1.0)
    m = spec.compile()
    d = mujoco.MjData(m)
    base = m.body(build.root_body).id
    poses = []
    for step in range(4000):
        d.ctrl[:] = (3.0, 5.0) if step < 2000 else (-4.0, 2.0)
        mujoco.mj_step(m, d)
        if step % 500 == 499:
            poses.append(np.r_[d.xpos[base], d.xquat[base]])
    return np.array(poses), int(m.nv), build.welded


def test_mbot_casters_are_welded_and_drive_exactly_as_hinged() -> None:
    model = RobotModel.from_path(MBOT)
    welded, nv_welded, names = _drive(model, weld=True)
    hinged, nv_hinged, none = _drive(model, weld=False)
    assert set(names) == {"front_caster_joint", "back_caster_joint"}
    assert none == ()
    assert (nv_welded, nv_hinged) == (8, 10)
    assert float(np.ptp(welded[:, 0])) > 0.1  # it drove
    assert np.max(np.abs(welded - hinged)) < 1e-9


def _robot(
    *, joint_extra: str = "", link_name: str = "caster", gazebo: str = "", xyz: str = "0 0 0"
) -> str:
    return f"""<robot name="r">
  <link name="base"><inertial><mass value="5"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
    <collision><geometry><box size="0.4 0.3 0.1"/></geometry></collision></link>
  <joint name="ball_joint" type="continuous"><parent link="base"/><child link="{link_name}"/>
    <origin xyz="0.15 0 -0.07"/><axis xyz="0 1 0"/>{joint_extra}</joint>
  <link name="{link_name}"><inertial><mass value="0.1"/>
    <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
    <collision><origin xyz="{xyz}"/><geometry><sphere radius="0.02"/></geometry></collision>
  </link>{gazebo}
</robot>"""


def _welded(urdf: str) -> tuple[str, ...]:
    world = empty_world()
    spec = new_spec(world.physics)
    add_world(spec, world)
    return add_robot(spec, RobotModel.from_string(urdf), name="r").welded


PUBLISHED = """<gazebo><plugin name="js" filename="libgazebo_ros_joint_state_publisher.so">
  <jointName>ball_joint</jointName></plugin></gazebo>"""


@pytest.mark.parametrize(
    ("urdf", "welded"),
    [
        (_robot(), ("ball_joint",)),
        (_robot(gazebo=PUBLISHED), ()),
        (_robot(joint_extra='<dynamics damping="0.01"/>'), ()),
        (
            _robot(
                link_name="ball",
                gazebo='<gazebo reference="ball"><mu1>0.5</mu1><mu2>0.5</mu2></gazebo>',
            ),
            (),
        ),
        (_robot(xyz="0.01 0 0"), ()),
        (_robot(xyz="0 0.01 0"), ("ball_joint",)),  # along the axis: still spins in place
    ],
    ids=["caster", "published", "damped", "with-friction", "off-axis", "along-axis"],
)
def test_only_joints_that_change_nothing_are_welded(urdf: str, welded: tuple[str, ...]) -> None:
    assert _welded(urdf) == welded
