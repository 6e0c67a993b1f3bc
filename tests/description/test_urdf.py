"""RobotModel: parsing, sources, tree queries, forward kinematics, and write/parse round trips."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from belvedere.description.urdf import (
    Box,
    Collision,
    Cylinder,
    Dynamics,
    GazeboExtension,
    Inertial,
    Joint,
    Limit,
    Link,
    Material,
    Mesh,
    Mimic,
    Pose,
    RobotModel,
    Sphere,
    Transmission,
    TransmissionJoint,
    URDFError,
    Visual,
    rpy_to_matrix,
)
from tests.conftest import DATA, EXAMPLES

MBOT = EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"
FULL = DATA / "urdf" / "check" / "valid_full.urdf"


@pytest.fixture(scope="module")
def mbot() -> RobotModel:
    return RobotModel.from_path(MBOT)


def test_seed_robot_forward_kinematics(mbot: RobotModel) -> None:
    poses = mbot.forward_kinematics()
    base = poses["base_link"]
    assert base[:3, 3] == pytest.approx([0, 0, 0.16 / 2 + 2 * 0.015])
    for wheel, y in (("left_wheel_link", -0.19), ("right_wheel_link", 0.19)):
        rel = np.linalg.inv(base) @ poses[wheel]
        assert rel[:3, 3] == pytest.approx([0, y, -0.05])
    assert mbot.root_link.name == "base_footprint"


def test_fk_follows_joint_positions_and_mimic() -> None:
    model = RobotModel.from_path(FULL)
    poses = model.forward_kinematics({"shoulder": math.pi / 2, "finger_a_joint": 0.5})
    # shoulder: origin z=1, pitch ~pi/2, then rotation about y by q
    expected = rpy_to_matrix((0, 1.5707963 + math.pi / 2, 0))
    assert poses["arm"][:3, :3] == pytest.approx(expected, abs=1e-9)
    a = np.linalg.inv(poses["hand"]) @ poses["finger_a"]
    b = np.linalg.inv(poses["hand"]) @ poses["finger_b"]
    assert a[:3, 3] == pytest.approx([0.5, 0, 0])
    assert b[:3, 3] == pytest.approx([-0.5, 0, 0])  # mimic multiplier -1


def test_tree_queries() -> None:
    model = RobotModel.from_path(FULL)
    assert model.root_link.name == "base"
    assert model.parent_link("hand") == "arm"
    assert model.children("base") == ("free", "plane", "arm", "slider")  # by joint name
    assert [j.name for j in model.chain("finger_a", "slider")] == [
        "finger_a_joint",
        "wrist",
        "shoulder",
        "slide",
    ]
    assert [j.name for j in model.chain("base", "hand")] == ["shoulder", "wrist"]
    assert {j.name for j in model.movable_joints} == {
        "shoulder",
        "wrist",
        "finger_a_joint",
        "finger_b_joint",
        "slide",
        "float",
        "planar",
    }
    with pytest.raises(KeyError, match="no link 'nope'"):
        model.link("nope")


def test_parts_are_parsed() -> None:
    model = RobotModel.from_path(FULL)
    base = model.link("base")
    assert base.inertial is not None
    assert base.inertial.mass == 1.0
    [visual] = base.visuals
    assert visual.geometry == Box((1.0, 2.0, 3.0))
    assert visual.origin == Pose((0.0, 0.0, 0.1), (0.0, 0.0, 1.57))
    assert visual.material_name == "blue"
    hand = model.link("hand")
    assert hand.visuals[1].geometry == Mesh("package://nowhere/hand.stl", (0.001, 0.001, 0.001))
    shoulder = model.joint("shoulder")
    assert shoulder.limit == Limit(10.0, 1.0, -1.0, 1.0)
    assert shoulder.dynamics == Dynamics(0.7, 0.1)
    assert model.joint("finger_b_joint").mimic == Mimic("finger_a_joint", -1.0, 0.0)
    # materials in urdfdom's registration order: global ones, then inline ones of first visuals
    assert [m.name for m in model.materials] == ["blue", "red"]
    assert model.materials[1].rgba == (1.0, 0.0, 0.0, 1.0)
    [t] = model.transmissions
    assert t.joints == (
        TransmissionJoint("shoulder", ("hardware_interface/EffortJointInterface",)),
    )
    assert t.actuators[0].mechanical_reduction == 50.0
    [g] = model.gazebo_for("base")
    assert g.property("material") == "Gazebo/Blue"
    assert g.property("mu1") == "0.2"


def test_legacy_transmission_format() -> None:
    model = RobotModel.from_path(DATA / "urdf" / "check" / "valid_legacy_transmission.urdf")
    [t] = model.transmissions
    assert t.legacy
    assert t.type == "pr2_mechanism_model/SimpleTransmission"
    assert t.actuators[0].mechanical_reduction == 1.0
    assert RobotModel.from_string(model.to_urdf()) == model


def test_gazebo_plugins_and_sensors_are_data(mbot: RobotModel) -> None:
    [robot_wide] = mbot.gazebo_for(None)
    [plugin] = robot_wide.plugins
    assert plugin.filename == "libgazebo_ros_diff_drive.so"
    assert plugin.param("wheelSeparation") == "0.38"
    assert plugin.param("legacyMode") == "true"


def test_sources_point_at_urdf_and_xacro_lines(mbot: RobotModel) -> None:
    wheel = mbot.link("left_wheel_link")
    assert wheel.source.urdf is not None
    assert wheel.source.urdf.path.endswith("mbot_gazebo.xacro (expanded)")
    assert wheel.source.xacro is not None
    line = Path(wheel.source.xacro.path).read_text().splitlines()[wheel.source.xacro.line - 1]
    assert 'link name="${prefix}_wheel_link"' in line
    model = RobotModel.from_path(FULL)
    assert model.joint("wrist").source.urdf is not None
    assert model.joint("wrist").source.xacro is None
    assert str(model.joint("wrist").source) == f"{FULL}:22:3"


def test_fatal_errors_raise_with_location() -> None:
    with pytest.raises(URDFError, match=r"invalid_two_roots\.urdf:2:1: error: two root links"):
        RobotModel.from_path(DATA / "urdf" / "check" / "invalid_two_roots.urdf")


def test_warnings_are_kept() -> None:
    model = RobotModel.from_path(
        DATA / "urdf" / "check" / "valid_box_without_size_drops_visual.urdf"
    )
    assert model.link("a").visuals == ()
    assert "box has no size attribute; urdfdom drops" in str(model.warnings[0])


def test_round_trip_of_examples(mbot: RobotModel) -> None:
    for model in (mbot, RobotModel.from_path(FULL)):
        again = RobotModel.from_string(model.to_urdf())
        assert again == model


# --- property-based round trips ------------------------------------------------------------

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)
positive = st.floats(min_value=1e-6, max_value=1e3, allow_nan=False)
vec3 = st.tuples(finite, finite, finite)
names = st.text(alphabet="abcdefghijklmnopqrstuvwxyz_0123456789", min_size=1, max_size=8)
poses = st.builds(Pose, vec3, vec3)
geometries = st.one_of(
    st.builds(Box, st.tuples(positive, positive, positive)),
    st.builds(Cylinder, positive, positive),
    st.builds(Sphere, positive),
    st.builds(Mesh, st.sampled_from(["package://p/m.stl", "meshes/a.dae"]), vec3),
)
colors = st.tuples(*[st.floats(0, 1)] * 4)


@st.composite
def robots(draw: st.DrawFn) -> RobotModel:
    link_names = draw(st.lists(names, min_size=1, max_size=6, unique=True))
    links = []
    for name in link_names:
        inertial = draw(
            st.none()
            | st.builds(Inertial, positive, finite, finite, finite, finite, finite, finite, poses)
        )
        visuals = draw(
            st.lists(
                st.builds(
                    Visual,
                    geometries,
                    poses,
                    st.none() | names,
                    st.none(),
                    st.none(),
                ),
                max_size=2,
            )
        )
        collisions = draw(
            st.lists(st.builds(Collision, geometries, poses, st.none() | names), max_size=2)
        )
        links.append(Link(name, inertial, tuple(visuals), tuple(collisions)))
    joints = []
    for i, name in enumerate(link_names[1:], start=1):
        parent = link_names[draw(st.integers(0, i - 1))]
        jtype = draw(
            st.sampled_from(["revolute", "continuous", "prismatic", "fixed", "floating", "planar"])
        )
        limit = (
            draw(st.builds(Limit, positive, positive, finite, finite))
            if jtype in ("revolute", "prismatic")
            else None
        )
        axis = draw(vec3) if jtype not in ("fixed", "floating") else (1.0, 0.0, 0.0)
        joints.append(
            Joint(
                f"j_{name}",
                jtype,  # type: ignore[arg-type]
                parent,
                name,
                draw(poses),
                axis,
                limit,
                draw(st.none() | st.builds(Dynamics, finite, finite)),
            )
        )
    materials = draw(
        st.lists(st.builds(Material, names, colors), max_size=2, unique_by=lambda m: m.name)
    )
    transmissions = tuple(
        Transmission(
            f"t_{j.name}",
            "transmission_interface/SimpleTransmission",
            (TransmissionJoint(j.name, ("hardware_interface/VelocityJointInterface",)),),
        )
        for j in joints[:1]
    )
    gazebo = (GazeboExtension(link_names[0], (("material", "Gazebo/Blue"),)),)
    return RobotModel(
        "generated", tuple(links), tuple(joints), tuple(materials), transmissions, gazebo
    )


@settings(max_examples=150, deadline=None)
@given(robots())
def test_write_then_parse_gives_an_equal_model(model: RobotModel) -> None:
    assert RobotModel.from_string(model.to_urdf()) == model


def test_prismatic_axis_is_made_unit_length_as_kdl_does() -> None:
    model = RobotModel.from_string(
        '<robot name="r"><link name="a"/><link name="b"/>'
        '<joint name="s" type="prismatic"><parent link="a"/><child link="b"/>'
        '<axis xyz="0 3 4"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    pose = model.forward_kinematics({"s": 0.5})["b"]
    assert pose[:3, 3] == pytest.approx([0.0, 0.3, 0.4])
