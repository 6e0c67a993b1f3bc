"""A world saved with a robot in it keeps the robot's plugins and sensors, as Gazebo's saved
SDF does: reloaded, the robot drives, publishes odometry and scans; spawning it again under its
name is refused with Gazebo's words."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from belvedere.description.urdf import Pose, RobotModel
from belvedere.graph import Graph, ZenohTransport
from belvedere.sim.physics import (
    SAVE_WORLD,
    SAVE_WORLD_TYPE,
    LaserSensor,
    PhysicsSimulation,
    save_world,
)
from belvedere.sim.physics._diff_drive import DiffDrive
from belvedere.world import SDFError, read_world, read_world_string, saved_robot
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]
LASER_MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
BOX_ROOM = EXAMPLES / "mbot_gazebo/worlds/box_room.world"


def _by_topic(text: str) -> dict[str, list[Any]]:
    """``--echo`` of several topics: each message by its topic."""
    out: dict[str, list[Any]] = {}
    for doc in text.split("\n---\n"):
        if doc.strip():
            header, _, body = doc.strip().partition("\n")
            out.setdefault(header.removeprefix("# "), []).append(yaml.safe_load(body))
    return out


def test_a_saved_robot_is_written_with_its_plugins_and_sensors(tmp_path: Path) -> None:
    """As sdformat converts it: the diff drive in the model, the laser in the link the laser's
    link is lumped into, posed there."""
    robot = RobotModel.from_path(LASER_MBOT)
    sim = PhysicsSimulation(Graph(), read_world(BOX_ROOM))
    sim.spawn(robot, name="mbot", pose=Pose((-1.0, 0.5, 0.0), (0.0, 0.0, 0.4)))
    saved = read_world(save_world(sim, tmp_path / "saved.world")).model("mbot")
    assert saved is not None
    assert saved.robot
    (plugin,) = saved.plugins
    (original,) = (p for g in robot.gazebo_for(None) for p in g.plugins)
    assert (plugin.name, plugin.filename) == ("differential_drive_controller", original.filename)
    assert [(p.tag, p.text.strip()) for p in plugin.params] == [
        (p.tag, p.text.strip()) for p in original.params
    ]
    base = saved.links[0]
    assert base.name == "base_footprint"
    (laser,) = base.sensors
    assert (laser.attr("name"), laser.attr("type")) == ("rplidar", "ray")
    # laser_link sits 0.105 m above base_link, itself 0.11 m above base_footprint
    pose = [float(v) for v in (laser.child_text("pose") or "").split()]
    np.testing.assert_allclose(pose, [0, 0, 0.215, 0, 0, 0], atol=1e-9)
    sensor_plugin = laser.child("plugin")
    assert sensor_plugin is not None
    assert sensor_plugin.attr("filename") == "libgazebo_ros_laser.so"
    assert sensor_plugin.child_text("frameName") == "laser_link"


def test_a_reloaded_robot_runs_its_plugins(tmp_path: Path) -> None:
    """In process: the saved robot is a robot of the reloaded simulation, its wheels jointed,
    its diff drive and laser running."""
    sim = PhysicsSimulation(Graph(), read_world(BOX_ROOM))
    sim.spawn(RobotModel.from_path(LASER_MBOT), name="mbot", pose=Pose((-1.0, 0.0, 0.0)))
    written = save_world(sim, tmp_path / "saved.world")
    graph = Graph()
    fresh = PhysicsSimulation(graph, read_world(written))
    assert list(fresh.robots) == ["mbot"]
    assert "mbot" not in fresh.world_roots  # not a rigid model of the world
    assert {type(p) for p in fresh.plugins} == {DiffDrive, LaserSensor}
    robot = fresh.robots["mbot"].model
    assert {j.name: j.type for j in robot.joints} == {
        "back_caster_joint": "continuous",
        "front_caster_joint": "continuous",
        "left_wheel_joint": "continuous",
        "right_wheel_joint": "continuous",
    }
    assert fresh.world_entry("mbot") is not None
    np.testing.assert_allclose(fresh.model_pose("mbot"), sim.model_pose("mbot"), atol=1e-6)


def test_a_model_that_cannot_be_a_robot_stays_rigid_and_says_why(
    caplog: pytest.LogCaptureFixture,
) -> None:
    world = read_world_string(
        "<sdf version='1.6'><world name='w'><model name='arm'>\n"
        "  <link name='a'/><link name='b'/>\n"
        "  <joint name='j' type='ball'><parent>a</parent><child>b</child></joint>\n"
        "  <plugin name='p' filename='libgazebo_ros_p3d.so'/>\n"
        "</model></world></sdf>\n",
        "arm.world",
    )
    entry = world.model("arm")
    assert entry is not None
    with pytest.raises(SDFError, match="joint 'j' is ball, which a URDF robot cannot have"):
        saved_robot(entry)
    sim = PhysicsSimulation(Graph(), world)
    assert "arm" in sim.world_roots
    assert "arm.world:3:3: warning: model 'arm' has plugins and sensors but cannot run" in (
        caplog.text
    )


def test_save_run_again_and_spawn_again_across_processes(endpoint: str, tmp_path: Path) -> None:
    """``sim`` in one terminal, the world saved from another through ``/gazebo/save_world``
    (what the viewer's Save World As calls); then the saved world run by the course's launch
    (its robot drives and scans), and ``sim --world`` of it with the same robot refused."""
    sim = subprocess.Popen(
        [*BELVEDERE, "sim", str(LASER_MBOT), "--world", str(BOX_ROOM), "--headless", "-x", "-1"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    probe = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
    caller = probe.create_node("caller")
    probe.start()
    target = tmp_path / "saved.world"
    try:

        def saved() -> bool:
            assert sim.poll() is None, sim.stderr.read() if sim.stderr else ""
            try:
                answer = caller.call_service(
                    SAVE_WORLD, SAVE_WORLD_TYPE, {"path": str(target)}, timeout=2.0
                )
            except Exception:  # noqa: BLE001 (not up yet)
                return False
            return bool(answer.success)

        wait_until(saved, what="the simulation to save its world", interval=0.5)
    finally:
        probe.shutdown()
        sim.terminate()
        sim.wait(timeout=DEADLINE)
    rerun = [*BELVEDERE, "sim", str(LASER_MBOT), "--world", str(target), "--headless"]
    again = subprocess.run(
        [*rerun, "--duration", "0.1"],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
    )
    assert again.returncode == 1
    assert "error: SpawnModel: Failure - model name mbot already exist." in again.stderr
    argv = [*BELVEDERE, "-q", "launch", "gazebo_ros", "empty_world.launch", "gui:=false"]
    argv += [f"world_name:={target}", "--headless", "--rtf", "max", "--duration", "2"]
    argv += ["--pub", "/cmd_vel geometry_msgs/Twist {linear: {x: 0.3}}"]
    argv += ["--echo", "/odom", "--echo", "/scan"]
    run = subprocess.run(argv, capture_output=True, text=True, timeout=5 * DEADLINE)
    assert run.returncode == 0, run.stderr
    assert "rigid" not in run.stderr
    messages = _by_topic(run.stdout)
    odom = messages["/odom"]
    start, end = (o["pose"]["pose"]["position"]["x"] for o in (odom[0], odom[-1]))
    assert abs(start + 1.0) < 0.01
    assert end - start > 0.3
    assert messages["/scan"]
    assert messages["/scan"][-1]["header"]["frame_id"] == "laser_link"


def test_an_sdf_model_with_plugins_spawns_as_a_robot() -> None:
    """spawn_sdf_model (``spawn_model -sdf``) of a model with plugins and sensors: a robot,
    as a saved one is, not a rigid model."""
    room = read_world(EXAMPLES / "mbot_gazebo/worlds/room.world")
    entry = room.model("mrobot")
    assert entry is not None
    sim = PhysicsSimulation(Graph(), read_world(BOX_ROOM))
    sim.add_model(entry, name="second", pose=Pose((1.0, 0.0, 0.0)))
    assert list(sim.robots) == ["second"]
    assert {type(p) for p in sim.plugins} == {DiffDrive, LaserSensor}
    np.testing.assert_allclose(sim.model_pose("second")[:3, 3], [1.0, 0.0, 0.0], atol=1e-9)
