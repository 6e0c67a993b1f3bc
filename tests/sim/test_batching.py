"""Physics batches with a plugin that wants every step: the course mbot driven into a wall,
its wheel motors at their torque limit, is stepped one step at a time inside one batch, and
moves and publishes exactly as when every step is a batch of its own."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import PhysicsSimulation
from belvedere.world import read_world
from tests.conftest import EXAMPLES

MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
WALL = """<?xml version="1.0"?>
<sdf version="1.6"><world name="wall">
  <include><uri>model://ground_plane</uri></include>
  <physics type="ode"><max_step_size>0.001</max_step_size></physics>
  <model name="wall"><static>true</static><pose>0.6 0 0.25 0 0 0</pose>
    <link name="link"><collision name="c"><geometry><box><size>0.1 3 0.5</size></box>
    </geometry></collision></link></model>
</world></sdf>
"""


def _drive(world: Path, *, one_step_batches: bool) -> tuple[list[Any], npt.NDArray[Any], int, int]:
    """Odometry and scans over 3 s of driving into the wall, the final state, how many times
    the physics timer ran and how many of its batches were stepped one step at a time."""
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world(world, packages=packages))
    sim.spawn(RobotModel.from_path(MBOT), name="mbot", packages=packages)
    if one_step_batches:
        sim.every_step.append(lambda: True)
    calls = [0]
    step = sim.physics_step

    def counted() -> None:
        calls[0] += 1
        step()

    sim.timer.callback = counted
    each = [0]
    step_each = sim._step_each

    def counted_each(*args: Any) -> None:
        each[0] += 1
        step_each(*args)

    setattr(sim, "_step_each", counted_each)  # noqa: B010 (an instance's method, counted)
    probe = graph.create_node("probe")
    got: list[Any] = []
    probe.subscribe("/odom", "nav_msgs/Odometry", got.append, queue_size=0)
    probe.subscribe("/scan", "sensor_msgs/LaserScan", got.append, queue_size=0)
    cmd = probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    cmd.publish_data({"linear": {"x": 0.4}})
    graph.run(duration=3.0)
    d = sim.engine.d
    state = np.concatenate([d.qpos, d.qvel, d.ctrl])
    graph.shutdown()
    return got, state, calls[0], each[0]


def test_a_capped_motor_is_stepped_inside_one_batch_exactly(tmp_path: Path) -> None:
    world = tmp_path / "wall.world"
    world.write_text(WALL)
    batched, state, calls, stepped = _drive(world, one_step_batches=False)
    single, single_state, single_calls, _ = _drive(world, one_step_batches=True)
    assert single_calls >= 3000  # every step its own batch
    assert calls < single_calls / 5
    assert stepped > 0  # the motors met their limit (starting, and at the wall)
    odom = [m for m in batched if hasattr(m, "pose")]
    assert odom[-1].pose.pose.position.x > 0.3  # reached the wall ...
    assert abs(odom[-1].twist.twist.linear.x) < 0.05  # ... and is stopped by it
    assert np.array_equal(state, single_state)
    assert len(batched) == len(single)
    for a, b in zip(batched, single, strict=True):
        assert a.header == b.header
        if hasattr(a, "pose"):
            assert a.pose.pose == b.pose.pose
            assert a.twist.twist == b.twist.twist
        else:
            assert np.array_equal(a.ranges, b.ranges)
