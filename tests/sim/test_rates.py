"""Sensors and plugins at Gazebo's rates (issue 13 §2): each fires on the first step at or past
its due time and carries the overshoot into the next period, so over 20 s of simulated time
a 5.5 Hz laser on 10 ms steps publishes 5.5 times a second (not 5.263), a 30 Hz camera 30
(not 25) — on worlds with 1, 4 and 10 ms steps alike."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.sim.physics import PhysicsSimulation
from belvedere.sim.physics._plugin import RateGate
from belvedere.world import empty_world

SENSORS = """<robot name="rates">
  <link name="base_footprint"><inertial><mass value="5"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
    <collision><origin xyz="0 0 0.05"/><geometry><box size="0.3 0.3 0.1"/></geometry>
    </collision></link>
  <joint name="spin" type="continuous"><parent link="base_footprint"/><child link="top"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 0 1"/></joint>
  <link name="top"><inertial><mass value="0.1"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <gazebo reference="base_footprint">
    <sensor type="ray" name="laser"><update_rate>5.5</update_rate>
      <ray><scan><horizontal><samples>36</samples><min_angle>-3.14</min_angle>
        <max_angle>3.14</max_angle></horizontal></scan><range><min>0.1</min><max>5</max></range>
      </ray>
      <plugin name="laser" filename="libgazebo_ros_laser.so"><topicName>/scan</topicName>
        <frameName>base_footprint</frameName></plugin>
    </sensor>
    <sensor type="camera" name="camera"><update_rate>30.0</update_rate>
      <camera><image><width>8</width><height>6</height></image></camera>
      <plugin name="camera" filename="libgazebo_ros_camera.so"><cameraName>/cam</cameraName>
      </plugin>
    </sensor>
    <sensor type="imu" name="imu"><update_rate>70</update_rate>
      <plugin name="imu" filename="libgazebo_ros_imu_sensor.so"><topicName>/imu</topicName>
      </plugin>
    </sensor>
  </gazebo>
  <gazebo>
    <plugin name="p3d" filename="libgazebo_ros_p3d.so"><bodyName>base_footprint</bodyName>
      <topicName>/truth</topicName><updateRate>7.7</updateRate></plugin>
    <plugin name="js" filename="libgazebo_ros_joint_state_publisher.so">
      <robotNamespace>/</robotNamespace><jointName>spin</jointName><updateRate>30</updateRate>
    </plugin>
  </gazebo>
</robot>"""

TOPICS = {
    "/scan": ("sensor_msgs/LaserScan", 5.5),
    "/cam/image_raw": ("sensor_msgs/Image", 30.0),
    "/imu": ("sensor_msgs/Imu", 70.0),
    "/truth": ("nav_msgs/Odometry", 7.7),
    "/joint_states": ("sensor_msgs/JointState", 30.0),
}
DURATION = 20.0


def _rates(step: float) -> dict[str, float]:
    world = empty_world()
    world = replace(world, physics=replace(world.physics, max_step_size=step))
    graph = Graph()
    sim = PhysicsSimulation(graph, world)
    sim.spawn(RobotModel.from_string(SENSORS), name="rates")
    probe = graph.create_node("probe")
    stamps: dict[str, list[int]] = {topic: [] for topic in TOPICS}
    for topic, (kind, _) in TOPICS.items():

        def record(msg: Any, topic: str = topic) -> None:
            stamps[topic].append(msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec)

        probe.subscribe(topic, kind, record, queue_size=0)
    graph.run(duration=DURATION + 1.0)
    out = {}
    for topic, times in stamps.items():
        inside = [t for t in times if 10**9 <= t < (DURATION + 1.0) * 10**9 - 1]
        out[topic] = (len(inside) - 1) / ((inside[-1] - inside[0]) / 1e9)
    return out


@pytest.mark.parametrize("step", [0.001, 0.004, 0.01])
def test_sensors_and_plugins_average_their_rates(step: float) -> None:
    rates = _rates(step)
    for topic, (_, rate) in TOPICS.items():
        assert rates[topic] == pytest.approx(rate, rel=0.005), topic


def test_a_gate_fires_on_the_first_step_past_its_period_and_carries_the_rest() -> None:
    ms = 1_000_000
    gate = RateGate(5.5, 0, strict=False, immediate=True)
    fired = [t for t in range(10 * ms, 2000 * ms + 1, 10 * ms) if gate.due(t)]
    assert fired[:4] == [10 * ms, 200 * ms, 380 * ms, 560 * ms]  # 190, 180, 180 ms apart
    assert len(fired) == 11  # 5.5 Hz over 2 s, not 2 / 0.19
    plugin = RateGate(100.0, 0)  # gazebo_ros plugins: elapsed > period
    assert [t for t in range(ms, 40 * ms, ms) if plugin.due(t)] == [11 * ms, 21 * ms, 31 * ms]
    behind = RateGate(1000.0, 0, strict=False)  # faster than the steps: once per step
    assert [behind.due(t * 10 * ms) for t in range(1, 4)] == [True, True, True]


def test_a_plugin_is_called_only_at_the_steps_it_is_due() -> None:
    """The laser (5.5 Hz) on a robot whose IMU publishes at 70 Hz: the physics stops for
    every IMU reading, and calls the laser only at its own."""
    graph = Graph()
    sim = PhysicsSimulation(graph, empty_world())
    robot = sim.spawn(RobotModel.from_string(SENSORS), name="rates")
    laser = next(p for p in robot.plugins if p.ctx.name == "laser")
    calls: list[int] = []
    update = laser.update

    def counted(now_ns: int) -> None:
        calls.append(now_ns)
        update(now_ns)

    setattr(laser, "update", counted)  # noqa: B010 (an instance's method, counted)
    probe = graph.create_node("probe")
    scans: list[Any] = []
    imu: list[Any] = []
    probe.subscribe("/scan", "sensor_msgs/LaserScan", scans.append, queue_size=0)
    probe.subscribe("/imu", "sensor_msgs/Imu", imu.append, queue_size=0)
    graph.run(duration=2.0)
    assert len(scans) == 11
    assert len(imu) >= 140
    assert calls == [m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for m in scans]
