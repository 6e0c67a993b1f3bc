"""Recording throughput: can ``belvedere bag record`` keep up with the physics simulation?

1. The reference, measured in the same run: the rate at which the physics simulation (the
   laser mbot in the playground, everything subscribed, as ``rosbag record -a`` makes it)
   publishes at ``--rtf max``, in messages per second.
2. The recorder (``TapRecording`` + ``Recorder``, as ``belvedere bag record`` runs them): another
   process floods it with the simulation's mix of messages (odometry, TF, joint states, laser
   scans, model states, clock) as fast as it can publish; messages per second from the first
   one received to the last one written, to a ROS 1 bag (CDR → ROS 1 for each message) and to
   MCAP (written as received). Nothing may be lost.

    python benchmarks/bag_record.py [--messages 20000]
"""

from __future__ import annotations

import argparse
import os
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
EXAMPLES = REPO / "examples"

FLOOD = """
import sys, time
from belvedere.graph import Graph, ZenohTransport
from belvedere.msgs import message_from_data
import numpy as np
transport = ZenohTransport(endpoint=sys.argv[1])
g = Graph(sim_time=True, transport=transport)
n = int(sys.argv[2])
node = g.create_node("flood")
mix = [
    ("/odom", "nav_msgs/Odometry", {"header": {"frame_id": "odom"}, "child_frame_id": "base"}, 4),
    ("/tf", "tf2_msgs/TFMessage", {"transforms": [{"header": {"frame_id": "odom"}}] * 2}, 4),
    ("/joint_states", "sensor_msgs/JointState",
     {"name": ["left", "right"], "position": [0.1, 0.2], "velocity": [1.0, 1.0]}, 4),
    ("/gazebo/model_states", "gazebo_msgs/ModelStates",
     {"name": ["ground_plane", "mbot", "box"], "pose": [{}, {}, {}], "twist": [{}, {}, {}]}, 6),
    ("/clock", "rosgraph_msgs/Clock", {}, 2),
    ("/scan", "sensor_msgs/LaserScan", {"ranges": [1.5] * 360, "intensities": [0.0] * 360}, 1),
]
order = []
pubs = {}
for topic, kind, data, weight in mix:
    pubs[topic] = (node.publisher(topic, kind, queue_size=100), message_from_data(kind, data))
    order += [topic] * weight
while not all(p.topic.remote for p, _ in pubs.values()):
    time.sleep(0.01)
print("READY", flush=True)
sys.stdin.readline()
for i in range(n):
    pub, msg = pubs[order[i % len(order)]]
    pub.publish(msg)
print("SENT", flush=True)
sys.stdin.readline()
g.shutdown()
"""


def free_endpoint() -> str:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{s.getsockname()[1]}"


def simulation_rate(seconds: float) -> float:
    """Messages per second the physics simulation publishes at --rtf max, all subscribed."""
    from belvedere.description.urdf import Pose, RobotModel
    from belvedere.graph import Graph
    from belvedere.packages import PackageIndex
    from belvedere.sim.physics import GazeboRos, PhysicsSimulation
    from belvedere.tf import JointStatePublisher, RobotStatePublisher
    from belvedere.world import read_world

    robot_file = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
    packages = PackageIndex.from_environment(near=str(robot_file))
    model = RobotModel.from_path(str(robot_file), packages=packages)
    graph = Graph(sim_time=True)
    world = read_world(EXAMPLES / "mbot_gazebo/worlds/playground.world", packages=packages)
    sim = PhysicsSimulation(graph, world)
    GazeboRos(sim, packages=packages)
    robot = sim.spawn(model, name=model.name, pose=Pose((0.5, 0, 0), (0, 0, 0)), packages=packages)
    RobotStatePublisher(graph.create_node("robot_state_publisher"), model)
    JointStatePublisher(
        graph.create_node("joint_state_publisher"), model, exclude=robot.published_joints()
    )
    count = [0]

    def sink(_: Any) -> None:
        count[0] += 1

    node = graph.create_node("sink")
    for name, topic in list(graph.topics.items()):
        node.subscribe(name, topic.type, sink, queue_size=0)
    start = time.perf_counter()
    graph.run(duration=seconds, rtf=None)
    return count[0] / (time.perf_counter() - start)


def record_rate(n: int, ext: str) -> tuple[float, int]:
    """(messages per second, messages recorded) of a recorder flooded with ``n``."""
    from belvedere.bags import Recorder, TapRecording, open_bag, parse_record_args
    from belvedere.graph import ZenohTransport

    endpoint = free_endpoint()
    out = Path(tempfile.mkdtemp()) / f"flood.{ext}"
    transport = ZenohTransport(endpoint=endpoint, serve_params=False)
    recorder = Recorder(parse_record_args(["-a", "-x", "/rosout", "-q", "-O", str(out)]))
    recorder.start(TapRecording(transport, recorder))
    env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
    flood = subprocess.Popen(
        [sys.executable, "-c", FLOOD, endpoint, str(n)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
        env=env,
    )
    assert flood.stdin is not None
    assert flood.stdout is not None
    assert flood.stdout.readline().strip() == "READY"
    flood.stdin.write("\n")
    flood.stdin.flush()
    while recorder.written == 0:
        time.sleep(0.0005)
    first = time.perf_counter()
    deadline = first + 600
    while recorder.written < n and time.perf_counter() < deadline:
        time.sleep(0.0005)
    last = time.perf_counter()
    flood.stdin.write("\n")
    flood.stdin.flush()
    flood.wait(timeout=60)
    recorder.stop()
    transport.close()
    bag = open_bag(out)
    recorded = sum(bag.counts.values())
    bag.close()
    return recorder.written / (last - first), recorded


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--messages", type=int, default=20000)
    parser.add_argument("--sim-seconds", type=float, default=3.0)
    args = parser.parse_args()
    sim = simulation_rate(args.sim_seconds)
    print(f"physics simulation at --rtf max, everything subscribed: {sim:8.0f} msg/s published")
    for ext in ("bag", "mcap"):
        rate, recorded = record_rate(args.messages, ext)
        lost = args.messages - recorded
        print(
            f"recorder to .{ext:4s}: {rate:8.0f} msg/s, {recorded}/{args.messages} recorded "
            f"({lost} lost) — {rate / sim:.1f}x the simulation's rate"
        )


if __name__ == "__main__":
    main()
