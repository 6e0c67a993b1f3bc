"""The SDF writer: what it writes reads back as the same world."""

from __future__ import annotations

from pathlib import Path

import pytest

from belvedere.description.urdf import RobotModel
from belvedere.errors import BelvedereError
from belvedere.world import ModelPaths, read_world, read_world_string, robot_entry, world_sdf
from tests.conftest import EXAMPLES

SHAPES = """<?xml version="1.0"?>
<sdf version="1.6">
  <world name="shapes">
    <gravity>0 0 -9.81</gravity>
    <physics type="ode"><max_step_size>0.002</max_step_size>
      <real_time_update_rate>500</real_time_update_rate></physics>
    <light name="lamp" type="spot">
      <pose>1 2 3 0 0.5 0</pose>
      <diffuse>0.9 0.8 0.7 1</diffuse>
      <attenuation><range>20</range><constant>0.5</constant><linear>0.1</linear>
        <quadratic>0.01</quadratic></attenuation>
      <direction>0 0 -1</direction>
      <spot><inner_angle>0.3</inner_angle><outer_angle>0.6</outer_angle><falloff>1</falloff></spot>
    </light>
    <model name="gadget">
      <pose>1 -2 0.5 0.1 0.2 0.3</pose>
      <link name="base">
        <pose>0 0 0.1 0 0 0</pose>
        <gravity>false</gravity>
        <inertial><pose>0.01 0 0 0 0 0</pose><mass>3</mass>
          <inertia><ixx>0.1</ixx><ixy>0.001</ixy><iyy>0.2</iyy><izz>0.3</izz></inertia>
        </inertial>
        <collision name="floor"><geometry><plane><normal>0 0 1</normal><size>2 3</size>
          </plane></geometry>
          <surface><friction><ode><mu>0.4</mu><mu2>0.5</mu2></ode></friction>
            <contact><ode><kp>100000</kp><kd>10</kd></ode></contact></surface>
        </collision>
        <visual name="prism"><pose>0 0 0.2 0 0 1</pose>
          <geometry><polyline><point>0 0</point><point>1 0</point><point>0 1</point>
            <height>0.4</height></polyline></geometry>
          <material><ambient>0.1 0.2 0.3 1</ambient><diffuse>0.4 0.5 0.6 1</diffuse>
            <specular>0.2 0.2 0.2 1</specular><emissive>0 0.1 0 1</emissive></material>
        </visual>
        <visual name="mesh"><geometry><mesh><uri>{mesh}</uri><scale>2 2 2</scale></mesh>
          </geometry></visual>
      </link>
      <link name="arm">
        <pose>0.5 0 0.1 0 0 0</pose>
        <collision name="c"><geometry><sphere><radius>0.05</radius></sphere></geometry>
        </collision>
      </link>
      <joint name="hinge" type="revolute">
        <parent>base</parent><child>arm</child>
        <axis><xyz>0 1 0</xyz><limit><lower>-1</lower><upper>2</upper></limit>
          <dynamics><damping>0.3</damping><friction>0.1</friction></dynamics></axis>
      </joint>
    </model>
  </world>
</sdf>
"""


def test_every_element_the_reader_knows_reads_back_the_same(tmp_path: Path) -> None:
    mesh = tmp_path / "part.stl"
    mesh.write_text("solid part\nendsolid part\n")
    world = read_world_string(SHAPES.format(mesh=mesh.name), str(tmp_path / "shapes.world"))
    assert world.warnings == ()
    text = world_sdf(world)
    assert f"<uri>file://{mesh}</uri>" in text  # any directory can read it back
    back = read_world_string(text, str(tmp_path / "elsewhere" / "saved.world"))
    assert back.warnings == ()
    assert back.models == world.models
    assert back.lights == world.lights
    assert back.physics == world.physics
    assert back.scene == world.scene


def test_a_robot_fixed_to_the_world_is_joined_to_world() -> None:
    """The world link is dropped; what is fixed to it becomes a link joined to ``world``;
    links fixed to a moving link are lumped into it."""
    arm = RobotModel.from_path(EXAMPLES / "marm_description/urdf/marm.xacro")
    entry = robot_entry(arm, name="marm")
    assert all(link.name != "world" for link in entry.links)
    to_world = [j for j in entry.joints if j.parent == "world"]
    assert [(j.type, j.child) for j in to_world] == [("fixed", entry.links[0].name)]
    moving = [j for j in arm.joints if j.type != "fixed"]
    assert {j.name for j in entry.joints} == {j.name for j in moving} | {to_world[0].name}


def test_the_writer_names_a_mesh_it_cannot_resolve_where_it_was_asked_for() -> None:
    urdf = """<robot name="r"><link name="a"><visual><geometry>
      <mesh filename="package://no_such_package/meshes/a.dae"/></geometry></visual></link>
    </robot>"""
    robot = RobotModel.from_string(urdf, path="r.urdf")
    with pytest.raises(BelvedereError, match=r"^r\.urdf:1:32: error: package 'no_such_package'"):
        robot_entry(robot, name="r")


def test_includes_keep_their_model_path_names(tmp_path: Path) -> None:
    model = tmp_path / "models" / "post"
    model.mkdir(parents=True)
    (model / "model.sdf").write_text(
        "<sdf version='1.6'><model name='post'><static>true</static><link name='l'>"
        "<collision name='c'><geometry><box><size>1 1 1</size></box></geometry></collision>"
        "</link></model></sdf>"
    )
    paths = ModelPaths((tmp_path / "models",))
    world = read_world_string(
        "<sdf version='1.6'><world name='w'><include><uri>model://post</uri><name>p1</name>"
        "<pose>1 2 0 0 0 0.5</pose><static>false</static></include></world></sdf>",
        model_paths=paths,
    )
    text = world_sdf(world)
    assert "<include>\n      <uri>model://post</uri>\n      <name>p1</name>" in text
    back = read_world_string(text, model_paths=paths)
    assert back.models == world.models
    assert read_world(tmp_path / "models/post/model.sdf").models[0].static
