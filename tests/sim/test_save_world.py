"""Saving the simulated world (File > Save World As, ``/gazebo/save_world``): what the file
holds, that it reloads to the same models at the same poses, and that a failed save loses
nothing."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.description.urdf import Pose, RobotModel
from belvedere.fileio import FileWriteError
from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from belvedere.sim.physics import (
    SAVE_WORLD,
    SAVE_WORLD_TYPE,
    GazeboRos,
    PhysicsSimulation,
    save_world,
)
from belvedere.world import ModelPaths, read_world
from belvedere.world._poses import matrix
from belvedere.xmldom import Element, parse_file
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE

MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"

CRATE = """<?xml version="1.0"?>
<sdf version="1.6">
  <model name="crate">
    <link name="link">
      <pose>0 0 0.2 0 0 0</pose>
      <inertial><mass>2</mass>
        <inertia><ixx>0.05</ixx><iyy>0.05</iyy><izz>0.05</izz></inertia></inertial>
      <collision name="collision"><geometry><box><size>0.4 0.4 0.4</size></box></geometry>
      </collision>
      <visual name="visual"><geometry><box><size>0.4 0.4 0.4</size></box></geometry></visual>
    </link>
  </model>
</sdf>
"""

WORLD = """<?xml version="1.0"?>
<sdf version="1.6">
  <world name="yard">
    <gui fullscreen="0">
      <camera name="user_camera"><pose>4 -4 3 0 0.5 2.3</pose></camera>
    </gui>
    <physics type="ode">
      <max_step_size>0.001</max_step_size>
      <real_time_update_rate>1000</real_time_update_rate>
      <ode><solver><iters>60</iters></solver></ode>
    </physics>
    <scene><ambient>0.3 0.3 0.3 1</ambient><sky><clouds><speed>12</speed></clouds></sky></scene>
    <include><uri>model://ground_plane</uri></include>
    <include><uri>model://sun</uri></include>
    <include><uri>model://crate</uri><name>crate_a</name><pose>1 0 0 0 0 0</pose></include>
    <include><uri>model://crate</uri><name>crate_b</name><pose>-1 1 0 0 0 0.5</pose></include>
    <model name="pillar">
      <static>true</static>
      <pose>0 2 0 0 0 0.3</pose>
      <link name="link">
        <pose>0 0 0.5 0 0 0</pose>
        <collision name="c"><geometry><cylinder><radius>0.2</radius><length>1</length>
        </cylinder></geometry></collision>
        <visual name="v"><geometry><cylinder><radius>0.2</radius><length>1</length>
        </cylinder></geometry><material><diffuse>0.8 0.1 0.1 1</diffuse></material></visual>
      </link>
    </model>
  </world>
</sdf>
"""


def _yard(tmp_path: Path) -> tuple[Path, ModelPaths]:
    """A world with includes of a model directory made here, an inline model and the
    built-in ground plane and sun."""
    crate = tmp_path / "models" / "crate"
    crate.mkdir(parents=True)
    (crate / "model.config").write_text(
        '<?xml version="1.0"?>\n<model><name>Crate</name><sdf version="1.6">model.sdf</sdf>'
        "</model>\n"
    )
    (crate / "model.sdf").write_text(CRATE)
    world = tmp_path / "yard.world"
    world.write_text(WORLD)
    return world, ModelPaths((tmp_path / "models",))


def _children(el: Element, tag: str) -> list[Element]:
    return [c for c in el.elements() if c.tag == tag]


def _text(el: Element, tag: str) -> str:
    return next(c for c in el.elements() if c.tag == tag).text_content().strip()


class Yard:
    """The yard simulated: the mbot spawned, one crate moved, two models added at runtime
    (one from the model path, one not)."""

    def __init__(self, tmp_path: Path) -> None:
        world_file, self.paths = _yard(tmp_path)
        self.graph = Graph()
        self.sim = PhysicsSimulation(self.graph, read_world(world_file, model_paths=self.paths))
        self.gazebo = GazeboRos(self.sim)
        self.sim.spawn(
            RobotModel.from_path(MBOT), name="mbot", pose=Pose((0.0, -1.5, 0.0), (0.0, 0.0, 0.8))
        )
        crate = read_world(tmp_path / "models/crate/model.sdf").models[0]
        self.sim.add_model(
            crate, name="crate_c", pose=Pose((2.0, 2.0, 0.0)), origin="model://crate"
        )
        self.sim.add_model(crate, name="loose_box", pose=Pose((-2.0, -2.0, 0.0), (0, 0, 1.0)))
        self.graph.run(duration=0.3)
        self.sim.set_model_pose("crate_a", Pose((1.5, -0.5, 0.0), (0.0, 0.0, 0.7)))
        self.graph.run(duration=0.5)


def test_a_saved_world_reloads_with_every_model_where_it_was(tmp_path: Path) -> None:
    yard = Yard(tmp_path)
    sim = yard.sim
    written = save_world(sim, tmp_path / "saved.world")
    assert written == (tmp_path / "saved.world").resolve()
    now = {name: sim.model_pose(name) for name in sim.model_names()}
    assert set(now) == {"ground_plane", "crate_a", "crate_b", "pillar", "crate_c", "loose_box"} | {
        "mbot"
    }
    assert abs(now["crate_a"][0, 3] - 1.5) < 1e-3  # it was moved, and stayed

    reloaded = read_world(written, model_paths=yard.paths)
    assert reloaded.warnings == ()
    fresh = PhysicsSimulation(Graph(), reloaded)
    assert set(fresh.model_names()) == set(now)
    for name, pose in now.items():
        np.testing.assert_allclose(fresh.model_pose(name), pose, atol=1e-6, err_msg=name)
    origins = {m.name: m.uri for m in reloaded.models}
    assert origins == {
        "ground_plane": "model://ground_plane",
        "crate_a": "model://crate",
        "crate_b": "model://crate",
        "crate_c": "model://crate",
        "pillar": None,
        "loose_box": None,
        "mbot": None,
    }
    assert reloaded.physics == sim.world.physics
    assert reloaded.scene == sim.world.scene
    assert reloaded.lights == sim.world.lights
    assert reloaded.name == "yard"


def test_includes_stay_includes_and_what_the_world_kept_is_kept(tmp_path: Path) -> None:
    yard = Yard(tmp_path)
    written = save_world(yard.sim, tmp_path / "saved.world")
    root = parse_file(written, namespaces=False, keep_blank=False).root
    assert root.tag == "sdf"
    assert root.attrs["version"] == "1.6"
    (world,) = _children(root, "world")
    includes = {_text(i, "name"): _text(i, "uri") for i in _children(world, "include")}
    assert includes == {
        "ground_plane": "model://ground_plane",
        "crate_a": "model://crate",
        "crate_b": "model://crate",
        "crate_c": "model://crate",
    }
    assert sorted(m.attrs["name"] for m in _children(world, "model")) == [
        "loose_box",
        "mbot",
        "pillar",
    ]
    (gui,) = _children(world, "gui")
    (camera,) = _children(gui, "camera")
    assert _text(camera, "pose") == "4 -4 3 0 0.5 2.3"
    (physics,) = _children(world, "physics")
    assert _text(_children(_children(physics, "ode")[0], "solver")[0], "iters") == "60"
    (scene,) = _children(world, "scene")
    assert _children(scene, "sky")
    (state,) = _children(world, "state")
    assert state.attrs["world_name"] == "yard"
    assert _text(state, "sim_time") == "0 800000000"
    assert _text(state, "iterations") == str(yard.sim.steps)
    seconds, nanoseconds = (int(v) for v in _text(state, "wall_time").split())
    assert seconds > 1_600_000_000
    assert 0 <= nanoseconds < 1_000_000_000
    state_models = {m.attrs["name"]: m for m in _children(state, "model")}
    assert set(state_models) == set(yard.sim.model_names())


def test_a_spawned_robot_is_written_as_gazebo_converts_it(tmp_path: Path) -> None:
    """Links joined by fixed joints lumped into one; every moving joint kept; each link in
    the state block where the simulation has it."""
    yard = Yard(tmp_path)
    sim = yard.sim
    written = save_world(sim, tmp_path / "saved.world")
    mbot = read_world(written, model_paths=yard.paths).model("mbot")
    assert mbot is not None
    assert [link.name for link in mbot.links] == [
        "base_footprint",
        "back_caster_link",
        "front_caster_link",
        "left_wheel_link",
        "right_wheel_link",
    ]
    assert {(j.name, j.type, j.parent, j.child) for j in mbot.joints} == {
        ("back_caster_joint", "revolute", "base_footprint", "back_caster_link"),
        ("front_caster_joint", "revolute", "base_footprint", "front_caster_link"),
        ("left_wheel_joint", "revolute", "base_footprint", "left_wheel_link"),
        ("right_wheel_joint", "revolute", "base_footprint", "right_wheel_link"),
    }
    base = mbot.links[0]
    assert base.inertial is not None
    robot = sim.robots["mbot"].model
    lumped = [link.inertial.mass for link in robot.links if link.inertial is not None]
    wheels_and_casters = sum(link.inertial.mass for link in mbot.links[1:] if link.inertial)
    assert base.inertial.mass + wheels_and_casters == pytest.approx(sum(lumped))
    assert "base_footprint_fixed_joint_lump__base_link_collision" in [
        c.name for c in base.collisions
    ]
    build = sim.robots["mbot"].build
    model_pose = sim.model_pose("mbot")
    for link in mbot.links:
        expected = np.linalg.inv(model_pose) @ sim.engine.link_pose(build, link.name)
        np.testing.assert_allclose(matrix(link.pose), expected, atol=1e-6, err_msg=link.name)


def test_saving_where_nothing_can_be_written_is_one_error_and_loses_nothing(
    tmp_path: Path,
) -> None:
    yard = Yard(tmp_path)
    folder = tmp_path / "worlds"
    folder.mkdir()
    with pytest.raises(FileWriteError) as err:
        save_world(yard.sim, folder)
    assert (
        err.value.describe()
        == f"error: cannot write {folder}: Is a directory; {folder} is unchanged"
    )
    missing = tmp_path / "no" / "such" / "dir.world"
    with pytest.raises(FileWriteError) as err:
        save_world(yard.sim, missing)
    assert err.value.describe() == (
        f"error: cannot write {missing}: No such file or directory; nothing was written"
    )
    with pytest.raises(FileWriteError, match=r"Not a directory"):
        save_world(yard.sim, tmp_path / "yard.world" / "x.world")
    assert sorted(p.name for p in folder.iterdir()) == []
    assert (tmp_path / "yard.world").read_text() == WORLD


def test_a_full_disk_keeps_the_world_that_was_there(tmp_path: Path, full_disk: Path) -> None:
    yard = Yard(tmp_path)
    target = full_disk / "saved.world"
    target.write_text("<sdf/>\n")
    (full_disk / "filler").write_bytes(b"\0" * 56 * 1024)
    with pytest.raises(FileWriteError) as err:
        save_world(yard.sim, target)
    assert err.value.describe() == (
        f"error: cannot write {target}: No space left on device; {target} is unchanged"
    )
    assert target.read_text() == "<sdf/>\n"
    assert sorted(p.name for p in full_disk.iterdir()) == ["filler", "saved.world"]


def test_the_service_saves_while_the_simulation_runs(tmp_path: Path) -> None:
    """``/gazebo/save_world`` called from another thread while the executor steps: the state
    is copied between steps, the file written on the caller's thread."""
    yard = Yard(tmp_path)
    caller = yard.graph.create_node("caller")
    yard.graph.start(rtf=None)
    try:
        started = yard.graph.now_ns()
        response = caller.call_service(
            SAVE_WORLD, SAVE_WORLD_TYPE, {"path": str(tmp_path / "running.world")}
        )
        assert response.success, response.status_message
        assert response.path == str((tmp_path / "running.world").resolve())
        assert response.status_message == f"SaveWorld: saved {response.path}"
        refused = caller.call_service(
            SAVE_WORLD, SAVE_WORLD_TYPE, {"path": str(tmp_path / "none" / "x.world")}
        )
        assert not refused.success
        assert refused.status_message == (
            f"SaveWorld: cannot write {tmp_path / 'none' / 'x.world'}: No such file or "
            "directory; nothing was written"
        )
        empty = caller.call_service(SAVE_WORLD, SAVE_WORLD_TYPE, {"path": " "})
        assert empty.status_message == (
            "SaveWorld: save world: give the path of the .world file to write"
        )
        assert yard.graph.now_ns() > started  # it never stopped
    finally:
        yard.graph.shutdown()
    saved = read_world(response.path, model_paths=yard.paths)
    assert {m.name for m in saved.models} == set(yard.sim.model_names())


def test_a_course_launch_file_runs_the_saved_world(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """As the course does: empty_world.launch with ``world_name`` set to the saved world,
    then the robot spawned into it."""
    yard = Yard(tmp_path)
    saved = save_world(yard.sim, tmp_path / "saved.world")
    now = {name: yard.sim.model_pose(name) for name in yard.sim.model_names()}
    monkeypatch.setenv("GAZEBO_MODEL_PATH", str(tmp_path / "models"))
    launch = tmp_path / "yard.launch"
    launch.write_text(
        f"""<launch>
  <include file="$(find gazebo_ros)/launch/empty_world.launch">
    <arg name="world_name" value="{saved}"/>
    <arg name="gui" value="false"/>
  </include>
  <param name="robot_description" textfile="$(find mbot_description)/urdf/urdf/mbot_base.urdf"/>
  <node name="urdf_spawner" pkg="gazebo_ros" type="spawn_model"
        args="-urdf -model mrobot -param robot_description -x 2 -y -2"/>
</launch>
"""
    )
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True)
    try:
        runtime.start()
        assert not runtime.missing
        sim = runtime.sim
        assert isinstance(sim, PhysicsSimulation)
        assert set(sim.model_names()) == {*now, "mrobot"}
        for name, pose in now.items():
            np.testing.assert_allclose(sim.model_pose(name), pose, atol=1e-6, err_msg=name)
        graph.run(duration=0.2)
        assert abs(sim.model_pose("mrobot")[0, 3] - 2.0) < 1e-3
    finally:
        runtime.close()
        graph.shutdown()


def test_a_call_before_the_simulation_starts_waits_for_it(tmp_path: Path) -> None:
    """A call from another process can come while the world is still being built (the
    service is offered before the robot is spawned): the snapshot waits for the executor."""
    world_file, paths = _yard(tmp_path)
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world(world_file, model_paths=paths))
    GazeboRos(sim)
    caller = graph.create_node("caller")
    responses: list[Any] = []
    target = str(tmp_path / "early.world")
    call = threading.Thread(
        target=lambda: responses.append(
            caller.call_service(SAVE_WORLD, SAVE_WORLD_TYPE, {"path": target})
        )
    )
    call.start()
    call.join(0.2)
    assert call.is_alive()  # waiting for the executor
    sim.spawn(RobotModel.from_path(MBOT), name="mbot")
    graph.start(rtf=None)
    try:
        call.join(DEADLINE)
    finally:
        graph.shutdown()
    (response,) = responses
    assert response.success, response.status_message
    saved = read_world(response.path, model_paths=paths)
    assert saved.model("mbot") is not None
