"""A joint whose lower limit is above its upper one: urdfdom accepts it, Gazebo's ODE ignores
both stops. ``check``, the physics simulator and the viewer say so in the same words, at the
joint's line, and the joint moves without limits in all of them (no crash of the slider)."""

from __future__ import annotations

import logging
import math
import socket
from pathlib import Path

import pytest

from belvedere.cli import main
from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.sim.physics import PhysicsSimulation
from belvedere.tf import JointStatePublisher
from belvedere.world import empty_world

URDF = """<?xml version="1.0"?>
<robot name="pendulum">
  <link name="world"/>
  <link name="post"><inertial><mass value="1"/>{inertia}</inertial></link>
  <joint name="anchor" type="fixed"><parent link="world"/><child link="post"/>
    <origin xyz="0 0 1"/></joint>
  <link name="arm"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>{inertia}</inertial></link>
  <joint name="shoulder" type="revolute">
    <parent link="post"/><child link="arm"/><axis xyz="0 1 0"/>
    <limit lower="{lower}" upper="{upper}" effort="10" velocity="10"/>
  </joint>
</robot>
"""
INERTIA = '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>'


def _write(tmp_path: Path, lower: float, upper: float) -> Path:
    path = tmp_path / "pendulum.urdf"
    path.write_text(URDF.format(inertia=INERTIA, lower=lower, upper=upper))
    return path


def _warning(path: Path) -> str:
    return (
        f"{path}:8:3: warning: joint 'shoulder': lower limit 0.5 > upper limit -0.5, so it "
        "moves without limits (Gazebo's ODE ignores limits the wrong way round, and so do "
        "belvedere's simulator and viewer)"
    )


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


def test_check_warns_at_the_joint(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _write(tmp_path, 0.5, -0.5)
    assert main(["check", str(path)]) == 0
    assert _warning(path) + "\n" in capsys.readouterr().err


def test_display_warns_once_and_runs(
    endpoint: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _write(tmp_path, 0.5, -0.5)
    assert main(["display", str(path), "--port", "0", "--duration", "0"]) == 0
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert err.count("lower limit") == 1
    assert _warning(path) + "\n" in err


def test_viewer_gives_the_joint_a_full_turn(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    from belvedere.viewer import Viewer

    model = RobotModel.from_path(_write(tmp_path, 0.5, -0.5))
    graph = Graph(sim_time=False)
    jsp = JointStatePublisher(graph.create_node("joint_state_publisher"), model)
    with caplog.at_level(logging.WARNING, logger="belvedere"):
        viewer = Viewer(graph, model=model, port=free_port(), joint_publisher=jsp)
    try:
        slider = viewer.sliders["shoulder"]
        assert (slider.min, slider.max, slider.value) == (-math.pi, math.pi, 0.0)
        assert [r.getMessage() for r in caplog.records] == [_warning(Path(model.path or ""))]
    finally:
        viewer.close()
        graph.shutdown()


def _swing(model: RobotModel) -> float:
    """Where the arm, released level, has swung after one second of gravity."""
    graph = Graph()
    sim = PhysicsSimulation(graph, empty_world())
    robot = sim.spawn(model, name="pendulum")
    graph.run(duration=1.0)
    joint = sim.engine.m.joint(robot.build.joints["shoulder"])
    return float(sim.engine.d.qpos[joint.qposadr[0]])


def test_physics_ignores_the_limits_as_gazebo_does(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    bounded = RobotModel.from_path(_write(tmp_path, -0.5, 0.5))
    assert _swing(bounded) == pytest.approx(0.5, abs=0.05)  # stopped by the upper limit
    inverted = RobotModel.from_path(_write(tmp_path, 0.5, -0.5))
    with caplog.at_level(logging.WARNING, logger="belvedere"):
        assert _swing(inverted) > 1.0  # swung on past both
    assert [r.getMessage() for r in caplog.records] == [_warning(Path(inverted.path or ""))]
