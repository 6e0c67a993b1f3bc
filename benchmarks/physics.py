"""The physics engine's speed. Gazebo classic runs the course's worlds at (at most) 1x real
time by default (real_time_update_rate 1000 with max_step_size 0.001); our reference here is
bare MuJoCo stepping the same compiled model in a loop, measured in the same run.

1. The course's mbot driving in the playground world, 1 kHz physics, 100 Hz diff drive, with
   an /odom subscriber: simulated seconds per wall second at rtf=max, and the ratio against
   bare ``mj_step`` on the same model (the cost of the graph, plugins and messages).
2. The laser mbot: a 360-beam scan at 5.5 Hz on top (with a /scan subscriber).
3. A camera mbot rendering 1280x720 images at 30 Hz while subscribed (offscreen, EGL).

    python benchmarks/physics.py [--seconds 10]
"""

from __future__ import annotations

import argparse
import importlib
import time
from pathlib import Path
from typing import Any

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import PhysicsSimulation
from belvedere.world import read_world

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
XACRO = EXAMPLES / "mbot_description/urdf/xacro/gazebo"
WORLD = EXAMPLES / "mbot_gazebo/worlds/playground.world"


def _scene(model_file: str, topics: dict[str, str]) -> tuple[Graph, PhysicsSimulation]:
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world(WORLD, packages=packages))
    sim.spawn(RobotModel.from_path(XACRO / model_file), name="mbot", packages=packages)
    probe = graph.create_node("probe")
    count = [0]

    def got(_: Any) -> None:
        count[0] += 1

    for topic, msg_type in topics.items():
        probe.subscribe(topic, msg_type, got, queue_size=0)
    cmd = probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    cmd.publish_data({"linear": {"x": 0.2}, "angular": {"z": 0.3}})
    return graph, sim


def run(model_file: str, topics: dict[str, str], seconds: float) -> tuple[float, float]:
    graph, sim = _scene(model_file, topics)
    started = time.perf_counter()
    graph.run(duration=seconds, rtf=None)
    ours = seconds / (time.perf_counter() - started)
    # imported after belvedere.sim.physics, which picks offscreen EGL rendering for MuJoCo
    mujoco = importlib.import_module("mujoco")
    m, d = sim.engine.m, sim.engine.d
    steps = round(seconds / m.opt.timestep)
    started = time.perf_counter()
    for _ in range(steps):
        mujoco.mj_step(m, d)
    bare = seconds / (time.perf_counter() - started)
    return ours, bare


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()
    cases = [
        ("mbot driving", "mbot_gazebo.xacro", {"/odom": "nav_msgs/Odometry"}),
        (
            "mbot + 360-beam laser",
            "mbot_with_laser_gazebo.xacro",
            {"/odom": "nav_msgs/Odometry", "/scan": "sensor_msgs/LaserScan"},
        ),
        (
            "mbot + 1280x720 camera",
            "mbot_with_camera_gazebo.xacro",
            {"/camera/image_raw": "sensor_msgs/Image"},
        ),
    ]
    for label, model_file, topics in cases:
        seconds = args.seconds if "camera" not in label else min(args.seconds, 2.0)
        ours, bare = run(model_file, topics, seconds)
        print(
            f"{label:26s} {ours:7.1f}x real time   bare mj_step {bare:7.1f}x   "
            f"ratio {ours / bare:.2f}   (Gazebo classic: 1x by default)"
        )


if __name__ == "__main__":
    main()
