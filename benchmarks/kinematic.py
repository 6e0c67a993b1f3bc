"""The kinematic engine's speed. The reference is the original: arbotix_driver runs on
rospy.Rate, tied to the wall clock, so it simulates at exactly 1x real time (ratio 1.0).

1. One robot (the course's mbot + its ArbotiX YAML, as ``belvedere sim --headless``) at
   ``--rtf max``, driven in a circle: simulated seconds per wall second (target >= 1000x).
   Measured with nobody listening, and with a TF listener and an /odom subscriber attached
   (what a viewer or a navigation stack adds).
2. 100 robots in one process, in namespaces, paced at real time with a listener on every
   robot's /odom and /tf: the share of one CPU core the process uses.

    python benchmarks/kinematic.py [--seconds 200] [--robots 100]
"""

from __future__ import annotations

import argparse
import resource
import time
from pathlib import Path
from typing import Any

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.sim.kinematic import ArbotixConfig, KinematicSimulation
from belvedere.tf import TFBuffer, TransformListener
from belvedere.yamlfile import load_yaml_file

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
MODEL = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo_modern.xacro"
CONFIG = EXAMPLES / "mbot_description/config/fake_mbot_arbotix.yaml"


def _robots(graph: Graph, count: int, *, listen: bool) -> list[Any]:
    model = RobotModel.from_path(MODEL)
    doc = load_yaml_file(CONFIG)
    config = ArbotixConfig.from_yaml(doc)
    sims = []
    probe = graph.create_node("probe")
    for i in range(count):
        ns = f"robot_{i}" if count > 1 else "/"
        sims.append(KinematicSimulation(graph, model, config, params=doc.data, namespace=ns))
        cmd = probe.publisher(f"{ns.rstrip('/')}/cmd_vel", "geometry_msgs/Twist", latch=True)
        cmd.publish_data({"linear": {"x": 0.2}, "angular": {"z": 0.5}})
        if listen:
            probe.subscribe(f"{ns.rstrip('/')}/odom", "nav_msgs/Odometry", lambda _: None)
    if listen:
        TransformListener(probe, TFBuffer())
    return sims


def one_robot(seconds: float, *, listen: bool) -> float:
    graph = Graph()
    _robots(graph, 1, listen=listen)
    started = time.perf_counter()
    graph.run(duration=seconds, rtf=None)
    return seconds / (time.perf_counter() - started)


def many_robots(count: int, seconds: float) -> float:
    graph = Graph()
    _robots(graph, count, listen=True)
    cpu0 = resource.getrusage(resource.RUSAGE_SELF)
    wall0 = time.perf_counter()
    graph.run(duration=seconds, rtf=1.0)
    wall = time.perf_counter() - wall0
    cpu1 = resource.getrusage(resource.RUSAGE_SELF)
    cpu = (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)
    return cpu / wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seconds", type=float, default=200.0)
    parser.add_argument("--robots", type=int, default=100)
    parser.add_argument("--paced-seconds", type=float, default=10.0)
    args = parser.parse_args()
    reference = 1.0  # arbotix_driver: rospy.Rate on the wall clock
    quiet = one_robot(args.seconds, listen=False)
    heard = one_robot(args.seconds, listen=True)
    print(f"one robot, rtf=max, nobody listening:   {quiet:8.0f}x real time")
    print(
        f"one robot, rtf=max, TF + odom listeners: {heard:8.0f}x real time "
        f"(ArbotiX: {reference:.0f}x; ratio {heard / reference:.0f}; target >= 1000x)"
    )
    share = many_robots(args.robots, args.paced_seconds)
    print(
        f"{args.robots} robots at real time, with listeners: {100 * share:.1f}% of one core "
        f"over {args.paced_seconds:g} s"
    )


if __name__ == "__main__":
    main()
