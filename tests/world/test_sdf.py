"""Reading Gazebo worlds and models."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from belvedere.description.urdf import Box, Cylinder
from belvedere.errors import ParseError
from belvedere.packages import PackageIndex
from belvedere.world import (
    ModelPaths,
    Plane,
    Polyline,
    SDFError,
    read_world,
    read_world_string,
)
from tests.conftest import EXAMPLES

WORLDS = EXAMPLES / "mbot_gazebo" / "worlds"


def _paths(*extra: Path) -> ModelPaths:
    return ModelPaths.from_environment(
        packages=PackageIndex([EXAMPLES]), environ={}, extra=tuple(extra)
    )


def test_playground_world() -> None:
    world = read_world(WORLDS / "playground.world", model_paths=_paths())
    assert world.physics.max_step_size == 0.001
    assert world.physics.gravity == (0.0, 0.0, -9.8)
    names = [m.name for m in world.models]
    assert names == [
        "ground_plane",
        "playground_walls",
        "crate_1",
        "crate_2",
        "post_1",
        "post_2",
        "table",
    ]
    assert [light.name for light in world.lights] == ["sun"]  # built in: no models installed
    ground = world.model("ground_plane")
    assert ground is not None
    assert isinstance(ground.links[0].collisions[0].geometry, Plane)
    walls = world.model("playground_walls")
    assert walls is not None
    assert walls.static
    assert [link.name for link in walls.links] == ["Wall_0", "Wall_1", "Wall_2", "Wall_3"]
    assert walls.links[1].pose.xyz == (4.0, 0.0, 0.5)
    assert walls.links[0].visuals[0].rgba == (0.7, 0.7, 0.7, 1.0)  # Gazebo/Grey
    # The saved <state> moved crate_1 from its <include> pose (2, 1) to (2.2, 1, yaw 0.3).
    crate = world.model("crate_1")
    assert crate is not None
    assert crate.pose.xyz == (2.2, 1.0, 0.0)
    assert crate.pose.rpy[2] == pytest.approx(0.3)
    assert crate.links[0].pose.xyz == pytest.approx((0.0, 0.0, 0.2))
    assert crate.uri == "model://belvedere_crate"
    assert crate.links[0].inertial is not None
    assert crate.links[0].inertial.mass == 4.0
    assert crate.links[0].collisions[0].surface is not None
    assert crate.links[0].collisions[0].surface.mu == 0.8
    # The table's legs are placed relative_to its top (SDF 1.7).
    table = world.model("table")
    assert table is not None
    leg = table.link("leg_front_left")
    assert leg is not None
    assert leg.pose.xyz == pytest.approx((0.55, 0.35, 0.36))
    assert table.pose.rpy[2] == pytest.approx(1.5708)


def test_missing_model_names_it_the_line_and_every_directory(tmp_path: Path) -> None:
    world = tmp_path / "w.world"
    world.write_text(
        "<sdf version='1.6'><world name='w'>\n"
        "  <include>\n    <uri>model://no_such_model</uri>\n  </include>\n"
        "</world></sdf>\n"
    )
    models = tmp_path / "models"
    models.mkdir()
    with pytest.raises(SDFError) as info:
        read_world(world, model_paths=_paths(models))
    text = info.value.describe()
    assert f"{world}:3:5: error: model 'model://no_such_model' not found" in text
    assert str(models) in text
    assert "never downloads" in text


def test_model_path_environment_and_home(tmp_path: Path) -> None:
    home = tmp_path / "home"
    (home / ".gazebo" / "models" / "thing").mkdir(parents=True)
    (home / ".gazebo" / "models" / "thing" / "model.sdf").write_text(
        "<sdf version='1.5'><model name='thing'><static>true</static><link name='l'>"
        "<collision name='c'><geometry><sphere><radius>0.3</radius></sphere></geometry>"
        "</collision></link></model></sdf>"
    )
    extra = tmp_path / "extra"
    extra.mkdir()
    paths = ModelPaths.from_environment(
        environ={"HOME": str(home), "GAZEBO_MODEL_PATH": str(extra)}
    )
    assert paths.directories[:2] == (extra, home / ".gazebo" / "models")
    world = read_world_string(
        "<sdf version='1.6'><world name='w'><include><uri>model://thing</uri>"
        "<pose>1 2 0 0 0 0</pose><name>ball</name></include></world></sdf>",
        model_paths=paths,
    )
    (ball,) = world.models
    assert (ball.name, ball.pose.xyz, ball.static) == ("ball", (1.0, 2.0, 0.0), True)


def test_poses_quaternions_degrees_and_old_gravity() -> None:
    world = read_world_string(
        """<sdf version='1.4'><world name='w'>
        <physics type='ode'><gravity>0 0 -3.7</gravity><max_step_size>0.002</max_step_size>
        </physics>
        <model name='a'><pose degrees='true'>0 0 0 0 0 90</pose>
          <link name='l'><pose rotation_format='quat_xyzw'>0 0 1 0 0 0.7071068 0.7071068</pose>
            <collision name='c'><geometry><polyline><point>0 0</point><point>1 0</point>
            <point>1 1</point><height>2</height></polyline></geometry></collision>
          </link>
        </model></world></sdf>""",
        model_paths=_paths(),
    )
    assert world.physics.gravity == (0.0, 0.0, -3.7)
    assert world.physics.max_step_size == 0.002
    (model,) = world.models
    assert model.pose.rpy[2] == pytest.approx(math.pi / 2)
    assert model.links[0].pose.rpy[2] == pytest.approx(math.pi / 2)
    geometry = model.links[0].collisions[0].geometry
    assert isinstance(geometry, Polyline)
    assert geometry.height == 2.0


@pytest.mark.parametrize(
    ("body", "where", "message"),
    [
        ("<model name='a'><pose>1 2</pose></model>", ":1:", "<pose> expects 6 numbers"),
        (
            "<model name='a'><link name='l'><pose relative_to='nope'>0 0 0 0 0 0</pose>"
            "</link></model>",
            ":1:",
            "pose of link 'l' is relative_to 'nope', which is not a frame of model 'a'",
        ),
        (
            "<model name='a'><link name='l'><collision name='c'><geometry><box>"
            "<size>1 x 1</size></box></geometry></collision></link></model>",
            ":1:",
            "<size> expects numbers",
        ),
        (
            "<model name='a'><link name='l'/></model><model name='a'><link name='m'/></model>",
            ":1:",
            "two models are named 'a'",
        ),
        (
            "<model name='a'><link name='l'/><joint name='j' type='revolute'><parent>l</parent>"
            "<child>zz</child></joint></model>",
            ":1:",
            "child link 'zz' is not a link of this model",
        ),
    ],
)
def test_errors_name_the_line(body: str, where: str, message: str) -> None:
    with pytest.raises(SDFError, match=message) as info:
        read_world_string(
            f"<sdf version='1.7'><world name='w'>{body}</world></sdf>",
            "bad.world",
            model_paths=_paths(),
        )
    assert f"bad.world{where}" in info.value.describe()


def test_include_cycle(tmp_path: Path) -> None:
    (tmp_path / "loop").mkdir()
    (tmp_path / "loop" / "model.sdf").write_text(
        "<sdf version='1.6'><model name='loop'><include><uri>model://loop</uri></include>"
        "</model></sdf>"
    )
    with pytest.raises(SDFError, match="include cycle"):
        read_world_string(
            "<sdf version='1.6'><world name='w'><include><uri>model://loop</uri></include>"
            "</world></sdf>",
            model_paths=_paths(tmp_path),
        )


def test_a_model_file_is_a_world_with_that_model() -> None:
    world = read_world(
        EXAMPLES / "mbot_gazebo/models/belvedere_post/model.sdf", model_paths=_paths()
    )
    (post,) = world.models
    assert isinstance(post.links[0].collisions[0].geometry, Cylinder)
    assert not isinstance(post.links[0].collisions[0].geometry, Box)


def test_malformed_xml_and_not_sdf() -> None:
    with pytest.raises(Exception, match=r"w\.world:1:.*malformed XML"):
        read_world_string("<sdf><world>", "w.world", model_paths=_paths())
    with pytest.raises(SDFError, match="expected an <sdf> document"):
        read_world_string("<gazebo version='1.0'/>", "w.world", model_paths=_paths())


@pytest.mark.parametrize("token", ["1e309", "Infinity", "-inf", "nan"])
def test_non_finite_numbers_are_errors_at_their_line(token: str) -> None:
    with pytest.raises(SDFError) as info:
        read_world_string(
            f"<sdf version='1.6'><world name='w'><model name='m'>\n<pose>{token} 0 0 0 0 0</pose>"
            "<link name='l'/></model></world></sdf>",
            "bad.world",
            model_paths=_paths(),
        )
    assert info.value.describe() == (
        f"bad.world:2:1: error: <pose> expects finite numbers, got {token!r}\n"
        "  hint: the largest double is ±1.7976931348623157e+308"
    )


def test_a_model_name_too_long_for_the_file_system_is_not_found() -> None:
    uri = "model://" + "x" * 300
    with pytest.raises(SDFError, match=r"model 'model://x{300}' not found \(searched: ") as info:
        read_world_string(
            f"<sdf version='1.6'><world name='w'><include>\n<uri>{uri}</uri></include>"
            "</world></sdf>",
            "long.world",
            model_paths=_paths(),
        )
    assert str(info.value.location) == "long.world:2:1"


def test_nesting_beyond_the_limit_is_one_error_at_the_element() -> None:
    def world(depth: int) -> str:
        models = "".join(f"<model name='m{i}'>" for i in range(depth))
        return f"<sdf version='1.6'><world name='w'>{models}<link name='l'/>" + (
            "</model>" * depth + "</world></sdf>"
        )

    # <sdf>, <world> and the <link> are three levels: 253 models still fit, 990 do not.
    inner = read_world_string(world(253), model_paths=_paths()).models[0].links[-1]
    assert inner.name == "::".join(f"m{i}" for i in range(1, 253)) + "::l"
    text = world(990)
    with pytest.raises(ParseError, match="elements nest more than 256 levels deep") as info:
        read_world_string(text, "deep.world", model_paths=_paths())
    column = text.index("<model name='m254'>") + 1
    assert str(info.value.location) == f"deep.world:1:{column}"


def test_a_long_chain_of_frames_declared_backwards() -> None:
    frames = [
        f"<frame name='f{i}'><pose relative_to='f{i - 1}'>1 0 0 0 0 0</pose></frame>"
        for i in range(1, 2000)
    ]
    world = read_world_string(
        "<sdf version='1.7'><world name='w'><model name='m'>"
        + "".join(reversed(frames))
        + "<frame name='f0'/><link name='l'><pose relative_to='f1999'>1 0 0 0 0 0</pose></link>"
        "</model></world></sdf>",
        model_paths=_paths(),
    )
    assert world.models[0].links[0].pose.xyz == pytest.approx((2000.0, 0.0, 0.0))
    with pytest.raises(SDFError, match=r"pose of 'a' is relative to itself through a -> b -> a"):
        read_world_string(
            "<sdf version='1.7'><world name='w'><model name='m'>"
            "<frame name='a'><pose relative_to='b'>0 0 0 0 0 0</pose></frame>"
            "<frame name='b'><pose relative_to='a'>0 0 0 0 0 0</pose></frame><link name='l'/>"
            "</model></world></sdf>",
            model_paths=_paths(),
        )
