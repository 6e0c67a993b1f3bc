"""A visual of the same shape at the same place as a collision is drawn by the collision geom
itself (one geom, not two, at every physics step); any other visual keeps a geom of its own.
Cameras drawing them and rays hitting them are in test_camera.py and test_sensors.py."""

from __future__ import annotations

import mujoco
import numpy as np

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import PhysicsSimulation
from belvedere.sim.physics._spec import COLLISION_GROUP, DRAWN_GROUP, VISUAL_GROUP
from belvedere.world import read_world
from tests.conftest import EXAMPLES

MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
PLAYGROUND = EXAMPLES / "mbot_gazebo/worlds/playground.world"


def _groups(m: mujoco.MjModel, prefix: str) -> dict[str, int]:
    return {
        m.geom(g).name: int(m.geom_group[g])
        for g in range(m.ngeom)
        if m.geom(g).name.startswith(prefix)
    }


def test_the_mbot_draws_its_collision_shapes_and_keeps_the_visuals_that_differ() -> None:
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world(PLAYGROUND, packages=packages))
    sim.spawn(RobotModel.from_path(MBOT), name="mbot", packages=packages)
    m = sim.engine.m
    groups = _groups(m, "mbot/")
    # the laser's visual is not its collision cylinder, and the footprint has no collision
    assert {n for n, g in groups.items() if g == VISUAL_GROUP} == {
        "mbot/base_footprint/visual_0",
        "mbot/laser_link/visual_0",
    }
    assert groups["mbot/laser_link/collision_0"] == COLLISION_GROUP
    drawn = {n for n, g in groups.items() if g == DRAWN_GROUP}
    assert drawn == {
        f"mbot/{link}/collision_0"
        for link in (
            "base_link",
            "left_wheel_link",
            "right_wheel_link",
            "front_caster_link",
            "back_caster_link",
        )
    }
    # drawn in the visual's colour: the course's wheels are Gazebo/Gray, the base yellow-ish
    wheel = m.geom("mbot/left_wheel_link/collision_0")
    assert wheel.matid[0] >= 0
    assert float(m.geom_rgba[wheel.id][3]) == 1.0
    # a world's models the same way: not one of the playground's visuals needs a geom
    world = [g for g in range(m.ngeom) if not m.geom(g).name.startswith("mbot/")]
    assert len(world) == 14
    assert all(m.geom_group[g] == DRAWN_GROUP for g in world)
    assert all(m.geom_contype[g] and m.geom_conaffinity[g] for g in world)


def _one_link(rgba: str, visual_xyz: str = "0 0 0") -> str:
    return f"""<robot name="r"><link name="base">
  <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
  </inertial>
  <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  <visual><origin xyz="{visual_xyz}"/><geometry><box size="0.2 0.2 0.2"/></geometry>
    <material name="m"><color rgba="{rgba}"/></material></visual>
</link></robot>"""


def test_a_transparent_or_moved_visual_keeps_its_own_geom() -> None:
    for urdf, drawn in (
        (_one_link("1 0 0 1"), True),
        (_one_link("1 0 0 0"), False),  # MuJoCo's rays skip alpha 0: the collision stays hidden
        (_one_link("1 0 0 1", visual_xyz="0 0 0.01"), False),
    ):
        sim = PhysicsSimulation(Graph())
        sim.spawn(RobotModel.from_string(urdf), name="r")
        m = sim.engine.m
        groups = _groups(m, "r/")
        assert (groups["r/base/collision_0"] == DRAWN_GROUP) is drawn
        assert ("r/base/visual_0" in groups) is not drawn
        if drawn:
            rgba = m.geom_rgba[m.geom("r/base/collision_0").id]
            assert np.allclose(rgba, [1, 0, 0, 1])
