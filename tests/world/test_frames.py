"""SDF frame semantics (SDF 1.7's pose frame semantics, and the older rules before it).

The cases follow the specification's own examples (the pendulum on a base, the tip frame,
canonical links, nested models, world frames, placement frames), written here as small
worlds with numbers of our own, and a world as Gazebo 11 saves one with a URDF robot in it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from belvedere.description.urdf import Pose, transform
from belvedere.packages import PackageIndex
from belvedere.world import ModelPaths, SDFError, WorldModel, WorldModelEntry, read_world_string
from belvedere.world._poses import from_matrix
from tests.conftest import EXAMPLES

HALF_PI = math.pi / 2


def _paths(*extra: Path) -> ModelPaths:
    return ModelPaths.from_environment(
        packages=PackageIndex([EXAMPLES]), environ={}, extra=tuple(extra)
    )


def _world(body: str, version: str = "1.7", *, extra: tuple[Path, ...] = ()) -> WorldModel:
    return read_world_string(
        f"<sdf version='{version}'><world name='w'>\n{body}\n</world></sdf>",
        "frames.world",
        model_paths=_paths(*extra),
    )


def _model(body: str, version: str = "1.7") -> WorldModelEntry:
    (model,) = _world(f"<model name='m'>{body}</model>", version).models
    return model


def _close(pose: Pose, xyz: tuple[float, float, float], rpy: tuple[float, float, float]) -> None:
    """Compare as transforms: two rpy triples can name one rotation."""
    expected = transform(Pose(xyz, rpy))
    np.testing.assert_allclose(transform(pose), expected, atol=1e-9)


def _in_world(model: WorldModelEntry, link: str) -> Pose:
    found = model.link(link)
    assert found is not None, link
    return from_matrix(transform(model.pose) @ transform(found.pose))


# --- the pendulum on a base, written both ways ----------------------------------------------------

PENDULUM_16 = """
<link name='base'><pose>0 0 0.4 0 0 0</pose></link>
<link name='bob'><pose>0 0.5 1.0 1.5707963267948966 0 0</pose></link>
<joint name='hinge' type='revolute'>
  <parent>base</parent><child>bob</child>
  <pose>0 0 0.5 0 0 0</pose>
  <axis><xyz>1 0 0</xyz></axis>
</joint>
"""

PENDULUM_17 = """
<link name='base'><pose>0 0 0.4 0 0 0</pose></link>
<link name='bob'><pose relative_to='hinge'>0 0 -0.5 0 0 0</pose></link>
<joint name='hinge' type='revolute'>
  <parent>base</parent><child>bob</child>
  <pose relative_to='base'>0 0 0.6 1.5707963267948966 0 0</pose>
  <axis><xyz>1 0 0</xyz></axis>
</joint>
"""


@pytest.mark.parametrize(("version", "body"), [("1.6", PENDULUM_16), ("1.7", PENDULUM_17)])
def test_the_pendulum_is_the_same_either_way(version: str, body: str) -> None:
    # 1.6: the bob in the model frame, the joint in the bob's frame. 1.7: the joint 0.6 m
    # above the base, rolled a quarter turn; the bob 0.5 m down the joint's z axis, which now
    # points along the model's -y: the bob hangs at y = +0.5, z = 1.0.
    model = _model(body, version)
    bob = model.link("bob")
    assert bob is not None
    _close(bob.pose, (0.0, 0.5, 1.0), (HALF_PI, 0.0, 0.0))
    (hinge,) = model.joints
    _close(hinge.pose, (0.0, 0.0, 0.5), (0.0, 0.0, 0.0))  # in the bob's frame
    assert hinge.axis == pytest.approx((1.0, 0.0, 0.0))


def test_a_frame_attached_to_a_link_places_a_visual() -> None:
    # The tip frame hangs 0.5 m below the bob, rolled back; a visual is written in it.
    body = PENDULUM_17.replace(
        "<link name='bob'><pose relative_to='hinge'>0 0 -0.5 0 0 0</pose></link>",
        "<link name='bob'><pose relative_to='hinge'>0 0 -0.5 0 0 0</pose>"
        "<visual name='marker'><pose relative_to='tip'>0.1 0 0 0 0 0</pose>"
        "<geometry><sphere><radius>0.05</radius></sphere></geometry></visual></link>",
    )
    body += (
        "<frame name='tip' attached_to='bob'><pose>0 0 -0.5 -1.5707963267948966 0 0</pose></frame>"
    )
    model = _model(body)
    (tip,) = model.frames
    assert tip.name == "tip"
    assert tip.attached_to == "bob"
    # bob at (0, 0.5, 1) rolled +90°: its -z is the model's +y, so the tip is at y = 1.0.
    _close(tip.pose, (0.0, 1.0, 1.0), (0.0, 0.0, 0.0))
    bob = model.link("bob")
    assert bob is not None
    (marker,) = bob.visuals
    _close(marker.pose, (0.1, 0.0, -0.5), (-HALF_PI, 0.0, 0.0))  # in the bob's frame


# --- what frames are attached to ------------------------------------------------------------------


def test_frames_attach_to_the_canonical_link_through_joints_and_frames() -> None:
    model = _model(
        """
        <link name='first'/>
        <link name='second'><pose>1 0 0 0 0 0</pose></link>
        <joint name='j' type='fixed'><parent>first</parent><child>second</child></joint>
        <frame name='on_model'><pose>0 0 1 0 0 0</pose></frame>
        <frame name='on_joint' attached_to='j'/>
        <frame name='on_frame' attached_to='on_joint'><pose>0 2 0 0 0 0</pose></frame>
        """
    )
    frames = {f.name: f for f in model.frames}
    assert model.canonical_link == "first"
    assert frames["on_model"].attached_to == "first"
    assert frames["on_joint"].attached_to == "second"  # a joint moves with its child
    assert frames["on_frame"].attached_to == "second"
    # Poses default to relative_to the frame attached to: the joint sits at its child.
    _close(frames["on_joint"].pose, (1.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    _close(frames["on_frame"].pose, (1.0, 2.0, 0.0), (0.0, 0.0, 0.0))


def test_canonical_link_attribute_and_static_models() -> None:
    model = _model("<frame name='f'/><link name='b'/><link name='a'/>")
    assert model.canonical_link == "b"  # the first link listed
    (named,) = _world(
        "<model name='m' canonical_link='a'><link name='b'/><link name='a'/><frame name='f'/>"
        "</model>"
    ).models
    assert named.canonical_link == "a"
    assert named.frames[0].attached_to == "a"
    (static,) = _world(
        "<model name='m'><static>true</static><link name='b'/><frame name='f'/></model>"
    ).models
    assert static.frames[0].attached_to is None  # a static model's frame is the world's
    (outer,) = _world(
        "<model name='o'><link name='l'/><frame name='f' attached_to='fixture'/>"
        "<model name='fixture'><static>true</static><link name='k'/></model></model>"
    ).models
    assert outer.frames[0].attached_to is None  # so is a static nested model's


def test_an_axis_expressed_in_another_frame() -> None:
    # The child is turned a quarter turn about z: the model's x axis is its -y.
    model = _model(
        """
        <link name='a'/>
        <link name='b'><pose>0 0 0 0 0 1.5707963267948966</pose></link>
        <frame name='tilted'><pose>0 0 0 0 0 3.141592653589793</pose></frame>
        <joint name='in_model' type='revolute'><parent>a</parent><child>b</child>
          <axis><xyz expressed_in='__model__'>1 0 0</xyz></axis></joint>
        <joint name='in_joint' type='revolute'><parent>a</parent><child>b</child>
          <axis><xyz>1 0 0</xyz></axis></joint>
        <joint name='in_frame' type='revolute'><parent>a</parent><child>b</child>
          <axis><xyz expressed_in='tilted'>1 0 0</xyz></axis></joint>
        """
    )
    axes = {j.name: j.axis for j in model.joints}
    assert axes["in_model"] == pytest.approx((0.0, -1.0, 0.0), abs=1e-12)
    assert axes["in_joint"] == pytest.approx((1.0, 0.0, 0.0), abs=1e-12)
    assert axes["in_frame"] == pytest.approx((0.0, 1.0, 0.0), abs=1e-12)


def test_use_parent_model_frame_before_1_7() -> None:
    model = _model(
        """
        <link name='a'/>
        <link name='b'><pose>0 0 0 0 0 1.5707963267948966</pose></link>
        <joint name='j' type='revolute'><parent>a</parent><child>b</child>
          <axis><xyz>1 0 0</xyz><use_parent_model_frame>true</use_parent_model_frame></axis>
        </joint>
        """,
        "1.6",
    )
    assert model.joints[0].axis == pytest.approx((0.0, -1.0, 0.0), abs=1e-12)


# --- nested models --------------------------------------------------------------------------------


def test_nested_model_frames_are_scoped() -> None:
    (outer,) = _world(
        """
        <model name='robot'>
          <pose>10 0 0 0 0 0</pose>
          <link name='body'/>
          <model name='arm'>
            <pose relative_to='body'>1 0 0 0 0 1.5707963267948966</pose>
            <link name='upper'><pose>1 0 0 0 0 0</pose></link>
            <frame name='wrist' attached_to='upper'><pose>0 0 0.5 0 0 0</pose></frame>
          </model>
          <link name='tool'><pose relative_to='arm::wrist'>0 0 0.1 0 0 0</pose></link>
          <link name='beside'><pose relative_to='arm'>0 1 0 0 0 0</pose></link>
          <joint name='mount' type='fixed'><parent>body</parent><child>arm::upper</child>
          </joint>
        </model>
        """,
        "1.8",
    ).models
    assert outer.pose.xyz == pytest.approx((10.0, 0.0, 0.0))
    upper = outer.link("arm::upper")
    assert upper is not None
    # arm's frame is at (1, 0, 0) turned +90°: its x axis is the robot's y.
    _close(upper.pose, (1.0, 1.0, 0.0), (0.0, 0.0, HALF_PI))
    tool = outer.link("tool")
    assert tool is not None
    _close(tool.pose, (1.0, 1.0, 0.6), (0.0, 0.0, HALF_PI))
    beside = outer.link("beside")
    assert beside is not None
    _close(beside.pose, (0.0, 0.0, 0.0), (0.0, 0.0, HALF_PI))  # arm's +y is the robot's -x
    wrist = {f.name: f for f in outer.frames}["arm::wrist"]
    assert wrist.attached_to == "arm::upper"
    assert [j.child for j in outer.joints] == ["arm::upper"]
    _close(_in_world(outer, "tool"), (11.0, 1.0, 0.6), (0.0, 0.0, HALF_PI))


def test_a_model_without_links_is_attached_through_its_nested_model() -> None:
    (outer,) = _world(
        "<model name='o'><frame name='f'/><model name='i'><link name='l'/></model></model>"
    ).models
    assert outer.canonical_link == "i::l"
    assert outer.frames[0].attached_to == "i::l"


# --- world frames, includes, placement frames -----------------------------------------------------


def test_world_frames_and_models_relative_to_them() -> None:
    world = _world(
        """
        <frame name='corner'><pose>2 3 0 0 0 1.5707963267948966</pose></frame>
        <frame name='above' attached_to='corner'><pose>0 0 1 0 0 0</pose></frame>
        <model name='box'><pose relative_to='corner'>1 0 0 0 0 0</pose><link name='l'/></model>
        <model name='lid'><pose relative_to='box'>0 0 0.5 0 0 0</pose><link name='l'/></model>
        <model name='tag'><pose relative_to='box::l'>0 0.2 0 0 0 0</pose><link name='l'/></model>
        <light name='lamp' type='point'><pose relative_to='above'>0 0 2 0 0 0</pose></light>
        """,
        "1.8",
    )
    box, lid, tag = (world.model(n) for n in ("box", "lid", "tag"))
    assert box is not None
    assert lid is not None
    assert tag is not None
    _close(box.pose, (2.0, 4.0, 0.0), (0.0, 0.0, HALF_PI))
    _close(lid.pose, (2.0, 4.0, 0.5), (0.0, 0.0, HALF_PI))
    _close(tag.pose, (1.8, 4.0, 0.0), (0.0, 0.0, HALF_PI))  # box's +y is the world's -x
    frames = {f.name: f for f in world.frames}
    _close(frames["above"].pose, (2.0, 3.0, 1.0), (0.0, 0.0, HALF_PI))
    assert frames["corner"].attached_to is None  # the world
    (lamp,) = world.lights
    _close(lamp.pose, (2.0, 3.0, 3.0), (0.0, 0.0, HALF_PI))


def _crate(tmp_path: Path, version: str = "1.7") -> Path:
    models = tmp_path / "models"
    (models / "crate").mkdir(parents=True)
    (models / "crate" / "model.sdf").write_text(
        f"<sdf version='{version}'><model name='crate'>"
        "<pose>5 0 0 0 0 0</pose>"
        "<link name='body'><pose>0 0 0.25 0 0 0</pose></link>"
        "<frame name='bottom' attached_to='body'><pose>0 0 -0.25 0 0 0</pose></frame>"
        "</model></sdf>"
    )
    return models


def test_an_include_pose_replaces_the_models_own(tmp_path: Path) -> None:
    models = _crate(tmp_path)
    world = _world(
        """
        <frame name='dock'><pose>0 -2 0 0 0 0</pose></frame>
        <include><uri>model://crate</uri><name>kept</name></include>
        <include><uri>model://crate</uri><name>moved</name><pose>1 0 0 0 0 0</pose></include>
        <include><uri>model://crate</uri><name>docked</name>
          <pose relative_to='dock'>1 0 0 0 0 0</pose></include>
        <include><uri>model://crate</uri><name>stood</name>
          <pose>0 0 1 0 0 0</pose><placement_frame>bottom</placement_frame></include>
        """,
        "1.8",
        extra=(models,),
    )
    poses = {m.name: m.pose.xyz for m in world.models}
    assert poses["kept"] == pytest.approx((5.0, 0.0, 0.0))  # the model file's pose
    assert poses["moved"] == pytest.approx((1.0, 0.0, 0.0))  # replaced, not added to
    assert poses["docked"] == pytest.approx((1.0, -2.0, 0.0))
    # The crate's bottom (0.25 below its body, the body 0.25 above the model frame) goes
    # to z = 1: so does the model frame.
    assert poses["stood"] == pytest.approx((0.0, 0.0, 1.0))


def test_a_placement_frame_on_a_model() -> None:
    (table,) = _world(
        """
        <model name='table' placement_frame='foot'>
          <pose>3 0 0 0 0 1.5707963267948966</pose>
          <link name='top'><pose>0 0 0.7 0 0 0</pose></link>
          <frame name='foot' attached_to='top'><pose>0.5 0 -0.7 0 0 0</pose></frame>
        </model>
        """,
        "1.8",
    ).models
    # The foot, 0.5 m along the table's x, is put at (3, 0, 0): the model frame is 0.5 m
    # back along the turned x axis (the world's y).
    _close(table.pose, (3.0, -0.5, 0.0), (0.0, 0.0, HALF_PI))


# --- older versions -------------------------------------------------------------------------------


def test_sdf_1_6_frame_attribute_and_1_7_ignores_it() -> None:
    body = (
        "<link name='a'><pose>1 0 0 0 0 0</pose></link>"
        "<link name='b'><pose frame='a'>0 1 0 0 0 0</pose></link>"
    )
    old = _model(body, "1.6").link("b")
    assert old is not None
    assert old.pose.xyz == pytest.approx((1.0, 1.0, 0.0))
    world = _world(f"<model name='m'>{body}</model>", "1.7")
    new = world.models[0].link("b")
    assert new is not None
    assert new.pose.xyz == pytest.approx((0.0, 1.0, 0.0))
    assert any("frame='a'" in w and "relative_to" in w for w in world.warnings)


def test_before_1_7_a_joint_may_share_a_links_name() -> None:
    body = (
        "<link name='a'/><link name='b'><pose>0 0 1 0 0 0</pose></link>"
        "<joint name='b' type='fixed'><parent>a</parent><child>b</child>"
        "<pose>0 0 0.5 0 0 0</pose></joint>"
        "<link name='c'><pose frame='b'>1 0 0 0 0 0</pose></link>"
    )
    model = _model(body, "1.6")
    c = model.link("c")
    assert c is not None
    assert c.pose.xyz == pytest.approx((1.0, 0.0, 1.0))  # the link b, not the joint
    assert model.joints[0].pose.xyz == pytest.approx((0.0, 0.0, 0.5))
    with pytest.raises(SDFError, match=r"model 'm' has a link and a joint both named 'b'"):
        _model(body.replace("frame=", "relative_to="), "1.7")


# --- a world saved by Gazebo 11 with a URDF robot in it -------------------------------------------

SAVED = """<sdf version='1.7'>
  <world name='default'>
    <model name='rover'>
      <link name='base_footprint'>
        <inertial><pose>0 0 0.1 0 -0 0</pose><mass>12</mass>
          <inertia><ixx>0.2</ixx><iyy>0.2</iyy><izz>0.3</izz></inertia></inertial>
        <collision name='base_footprint_fixed_joint_lump__base_link_collision'>
          <pose>0 0 0.1 0 -0 0</pose>
          <geometry><cylinder><length>0.12</length><radius>0.18</radius></cylinder></geometry>
        </collision>
      </link>
      <joint name='caster_joint' type='revolute'>
        <pose relative_to='base_footprint'>-0.15 0 0.02 0 -0 0</pose>
        <parent>base_footprint</parent>
        <child>caster_link</child>
        <axis><xyz>0 1 0</xyz><limit><lower>-1e+16</lower><upper>1e+16</upper></limit></axis>
      </joint>
      <link name='caster_link'>
        <pose relative_to='caster_joint'>0 0 0 0 -0 0</pose>
        <collision name='caster_link_collision'>
          <geometry><sphere><radius>0.02</radius></sphere></geometry>
        </collision>
      </link>
      <joint name='left_wheel_joint' type='revolute'>
        <pose relative_to='base_footprint'>0 0.17 0.05 0 -0 0</pose>
        <parent>base_footprint</parent>
        <child>left_wheel_link</child>
        <axis><xyz>0 1 0</xyz></axis>
      </joint>
      <link name='left_wheel_link'>
        <pose relative_to='left_wheel_joint'>0 0 0 0 -0 0</pose>
        <collision name='left_wheel_link_collision'>
          <pose>0 0 0 1.5708 -0 0</pose>
          <geometry><cylinder><length>0.02</length><radius>0.05</radius></cylinder></geometry>
        </collision>
      </link>
      <joint name='laser_joint' type='fixed'>
        <pose relative_to='base_footprint'>0.1 0 0.2 0 -0 0.5</pose>
        <parent>base_footprint</parent>
        <child>laser_link</child>
      </joint>
      <link name='laser_link'>
        <pose relative_to='laser_joint'>0.02 0 0.01 0 -0 0</pose>
      </link>
      <static>0</static>
      <pose>1 2 0 0 -0 1.5707963267948966</pose>
    </model>
  </world>
</sdf>
"""


def test_a_world_gazebo_11_saved_with_a_robot_in_it() -> None:
    world = read_world_string(SAVED, "saved.world", model_paths=_paths())
    rover = world.model("rover")
    assert rover is not None
    assert [lk.name for lk in rover.links] == [
        "base_footprint",
        "caster_link",
        "left_wheel_link",
        "laser_link",
    ]
    caster, wheel, laser = (rover.link(n) for n in ("caster_link", "left_wheel_link", "laser_link"))
    assert caster is not None
    assert wheel is not None
    assert laser is not None
    _close(caster.pose, (-0.15, 0.0, 0.02), (0.0, 0.0, 0.0))
    _close(wheel.pose, (0.0, 0.17, 0.05), (0.0, 0.0, 0.0))
    # The laser sits 2 cm along its joint's x, which is turned 0.5 rad.
    _close(laser.pose, (0.1 + 0.02 * math.cos(0.5), 0.02 * math.sin(0.5), 0.21), (0.0, 0.0, 0.5))
    # In the world, the rover is at (1, 2) facing +y: its -x is the world's -y.
    _close(_in_world(rover, "caster_link"), (1.0, 1.85, 0.02), (0.0, 0.0, HALF_PI))
    _close(_in_world(rover, "left_wheel_link"), (0.83, 2.0, 0.05), (0.0, 0.0, HALF_PI))
    joints = {j.name: j for j in rover.joints}
    for name in ("caster_joint", "left_wheel_joint"):
        _close(joints[name].pose, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))  # at the child
    _close(joints["laser_joint"].pose, (-0.02, 0.0, -0.01), (0.0, 0.0, 0.0))  # in the child
    assert joints["caster_joint"].axis == pytest.approx((0.0, 1.0, 0.0))
    assert rover.canonical_link == "base_footprint"


def test_the_saved_world_with_the_laser_joint_written_after_its_link() -> None:
    moved = SAVED.replace(
        "<link name='laser_link'>\n"
        "        <pose relative_to='laser_joint'>0.02 0 0.01 0 -0 0</pose>\n"
        "      </link>\n",
        "",
    ).replace(
        "<static>0</static>",
        "<link name='laser_link'><pose relative_to='laser_joint'>0.02 0 0.01 0 -0 0</pose>"
        "</link><static>0</static>",
    )
    assert moved != SAVED
    rover = read_world_string(moved, "saved.world", model_paths=_paths()).model("rover")
    assert rover is not None
    laser = rover.link("laser_link")
    assert laser is not None
    assert laser.pose.xyz[2] == pytest.approx(0.21)


# --- errors ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("body", "line", "message"),
    [
        (
            "<link name='a'>\n<pose relative_to='j'/></link><link name='p'/>"
            "<joint name='j' type='fixed'><parent>p</parent><child>a</child></joint>",
            3,
            r"pose of '(a|j)' is relative to itself through (a -> j -> a|j -> a -> j)",
        ),
        (
            "<link name='l'/><frame name='f1' attached_to='f2'/>\n"
            "<frame name='f2' attached_to='f1'/>",
            2,
            r"frame 'f1' is attached to itself through f1 -> f2 -> f1",
        ),
        (
            "<link name='l'/>\n<frame name='f' attached_to='lnk'/>",
            3,
            r"frame 'f' is attached_to 'lnk', which is not a frame of model 'm'",
        ),
        (
            "<link name='base'/><link name='caster'>\n<pose relative_to='caster_jiont'/></link>"
            "<joint name='caster_joint' type='fixed'><parent>base</parent><child>caster</child>"
            "</joint>",
            3,
            r"pose of link 'caster' is relative_to 'caster_jiont', which is not a frame",
        ),
        (
            "<link name='l'>\n<pose relative_to='world'/></link>",
            3,
            r"relative_to 'world', which is not a frame of model 'm'",
        ),
        (
            "<link name='l'/>\n<joint name='l' type='fixed'><parent>l</parent><child>l</child>"
            "</joint>",
            3,
            r"model 'm' has a link and a joint both named 'l' \(the first at frames\.world:2:",
        ),
        ("<link name='l'/>\n<link name='__model__'/>", 3, r"link name '__model__' is reserved"),
        ("<link name='l'/>\n<frame name='world'/>", 3, r"frame name 'world' is reserved"),
        (
            "<link name='l'/><link name='v'>\n<visual name='s'><pose relative_to='nope'/>"
            "<geometry><sphere><radius>1</radius></sphere></geometry></visual></link>",
            3,
            r"pose of visual 's' is relative_to 'nope'",
        ),
        (
            "<link name='a'/><link name='b'/>\n<joint name='j' type='revolute'><parent>a</parent>"
            "<child>b</child><axis><xyz expressed_in='nope'>1 0 0</xyz></axis></joint>",
            3,
            r"the axis of joint 'j' is relative_to 'nope'",
        ),
    ],
)
def test_frame_errors_name_the_place(body: str, line: int, message: str) -> None:
    with pytest.raises(SDFError, match=message) as info:
        _model(body)
    assert info.value.location is not None
    assert info.value.location.path == "frames.world"
    assert info.value.location.line == line


def test_unknown_frames_suggest_the_near_one_and_list_the_rest() -> None:
    with pytest.raises(SDFError) as info:
        _model(
            "<link name='base'/><link name='caster'><pose relative_to='caster_jiont'/></link>"
            "<joint name='caster_joint' type='fixed'><parent>base</parent><child>caster</child>"
            "</joint>"
        )
    assert info.value.hint == (
        "did you mean 'caster_joint'? frames of this model: __model__, base, caster, caster_joint"
    )


def test_a_canonical_link_that_is_not_a_link() -> None:
    with pytest.raises(SDFError, match=r"canonical_link 'f' is not a link of it") as info:
        _world("<model name='m' canonical_link='f'><link name='l'/><frame name='f'/></model>")
    assert info.value.hint == "links: l"


def test_world_frame_errors() -> None:
    with pytest.raises(SDFError, match=r"pose of model 'b' is relative_to 'nowhere'.*world 'w'"):
        _world("<model name='b'><pose relative_to='nowhere'/><link name='l'/></model>")
    with pytest.raises(SDFError, match=r"pose of 'a' is relative to itself through a -> b -> a"):
        _world(
            "<model name='a'><pose relative_to='b'/><link name='l'/></model>"
            "<model name='b'><pose relative_to='a'/><link name='l'/></model>"
        )
    with pytest.raises(SDFError, match=r"world 'w' has a model and a frame both named 'x'"):
        _world("<model name='x'><link name='l'/></model><frame name='x'/>")
