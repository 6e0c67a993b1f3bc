"""The course's camera (1280x720 at 30 Hz, mbot_description's camera xacro) in the empty world,
subscribed from another process with queue size 1, as ``belvedere topic echo --noarr`` does.

Prints: the real-time factor of the simulation (``--rtf max``: as fast as it goes), the frames
per second the other process received, the per-frame costs of rendering, encoding (the Image
message) and sending (serialization + Zenoh), the frames superseded by newer ones, and the
age of the delivered frames (wall-clock from publication to arrival, and how far the
simulation had gone on by then).

    python benchmarks/camera.py [--seconds 6] [--rtf max|1]
"""

from __future__ import annotations

import argparse
import bisect
import json
import os
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph, ZenohTransport
from belvedere.sim.physics import CameraSensor, PhysicsSimulation
from belvedere.world import empty_world

ROOT = Path(__file__).resolve().parents[1]
ROBOT = ROOT / "examples/mbot_description/urdf/xacro/gazebo/mbot_with_camera_gazebo.xacro"

# The other process: a queue-size-1 subscriber recording (arrival wall time, stamp) of each
# frame, until its stdin closes.
SUBSCRIBER = """
import json, sys, threading, time
from belvedere.graph import Graph, ZenohTransport
g = Graph(sim_time=False, transport=ZenohTransport(endpoint=sys.argv[1], role="connect"))
frames = []
def on_image(msg):
    frames.append((time.time(), msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec,
                   len(msg.data)))
g.create_node("camera_listener").subscribe("/camera/image_raw", "sensor_msgs/Image", on_image,
                                           queue_size=1)
g.start(rtf=None)
print("READY", flush=True)
sys.stdin.read()
time.sleep(0.5)
g.shutdown()
print(json.dumps(frames), flush=True)
"""


def free_endpoint() -> str:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{s.getsockname()[1]}"


def stock_cost(sim: PhysicsSimulation, camera: CameraSensor, frames: int = 10) -> float:
    """The reference, in the same run: seconds per frame of what belvedere did before —
    MuJoCo's stock Renderer (4x multisampled offscreen buffer, a new array and a flip per
    frame) and rosbags' serialization plus a copy to bytes."""
    import mujoco

    from belvedere.msgs import types

    m = sim.engine.m
    samples = m.vis.quality.offsamples
    m.vis.quality.offsamples = 4
    renderer = mujoco.Renderer(m, camera.height, camera.width)
    m.vis.quality.offsamples = samples
    store = types().store
    start = time.perf_counter()
    for _ in range(frames):
        renderer.update_scene(sim.engine.d, camera=camera.camera_name)
        image = camera.image(0, renderer.render())
        bytes(store.serialize_cdr(image, image.__msgtype__))
    seconds = (time.perf_counter() - start) / frames
    renderer.close()
    return seconds


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=6.0, help="simulated seconds")
    parser.add_argument("--rtf", default="max", help="max (default) or a real-time factor")
    args = parser.parse_args()
    rtf = None if args.rtf == "max" else float(args.rtf)

    endpoint = free_endpoint()
    graph = Graph(sim_time=True, transport=ZenohTransport(endpoint=endpoint, role="listen"))
    sim = PhysicsSimulation(graph, empty_world())
    robot = sim.spawn(RobotModel.from_path(ROBOT), name="mbot")
    camera = next(p for p in robot.plugins if isinstance(p, CameraSensor))
    published: list[tuple[int, float]] = []  # (stamp ns, wall time)
    timeline: list[tuple[float, int]] = []  # (wall time, sim ns) after each physics step

    publish = camera.image_pub.publish

    def publish_and_log(msg: Any) -> None:
        stamp = msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
        published.append((stamp, time.time()))
        publish(msg)

    camera.image_pub.publish = publish_and_log  # type: ignore[method-assign]
    sim.after_step.append(lambda: timeline.append((time.time(), graph.now_ns())))

    listener = subprocess.Popen(
        [sys.executable, "-c", SUBSCRIBER, endpoint],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert listener.stdout is not None
    assert listener.stdin is not None
    assert listener.stdout.readline().strip() == "READY"
    deadline = time.monotonic() + 20
    while not camera.image_pub.wanted and time.monotonic() < deadline:
        time.sleep(0.01)
    if not camera.image_pub.wanted:
        print("the subscriber never showed up", file=sys.stderr)
        return 1

    start = time.perf_counter()
    graph.run(duration=args.seconds, rtf=rtf)
    wall = time.perf_counter() - start
    assert isinstance(graph.transport, ZenohTransport)
    graph.transport.flush()
    listener.stdin.close()
    frames: list[tuple[float, int, int]] = json.loads(listener.stdout.read())
    listener.wait()
    graph.shutdown()
    camera.renderer.close()
    reference = stock_cost(sim, camera)

    render = camera.renderer
    stats = graph.transport.stats.get("/camera/image_raw")
    sent = stats.sent if stats else 0
    published_at = dict(published)
    ages = [arrival - published_at[stamp] for arrival, stamp, _ in frames if stamp in published_at]
    walls = [t for t, _ in timeline]
    lags = []  # how much simulated time had passed since the frame's stamp when it arrived
    for arrival, stamp, _ in frames:
        i = min(bisect.bisect_right(walls, arrival), len(timeline)) - 1
        lags.append((timeline[i][1] - stamp) / 1e9 if i >= 0 else 0.0)
    complete = all(size == 1280 * 720 * 3 for *_, size in frames)

    print(f"camera 1280x720 at 30 Hz, {args.seconds:g} simulated s, rtf {args.rtf}")
    print(f"  real-time factor            {args.seconds / wall:6.2f}x  ({wall:.2f} s wall)")
    print(f"  frames rendered             {render.frames:6d}  ({render.frames / wall:.1f}/s)")
    print(
        f"  frames sent                 {sent:6d}  superseded by newer: "
        f"{stats.superseded if stats else 0}"
    )
    print(
        f"  frames delivered            {len(frames):6d}  ({len(frames) / wall:.1f}/s to the "
        f"other process; complete: {complete})"
    )
    if render.frames:
        print(f"  render + read back / frame  {1e3 * render.seconds / render.frames:6.1f} ms")
        print(
            f"  encode (Image) / frame      {1e3 * camera.encode_seconds / render.frames:6.2f} ms"
        )
    if render.frames and sent and stats:
        ours = (render.seconds + camera.encode_seconds) / render.frames + stats.serialize_s / sent
        print(
            f"  render+encode+serialize     {1e3 * ours:6.1f} ms per frame; before (stock "
            f"Renderer, rosbags): {1e3 * reference:.1f} ms; ratio {reference / ours:.2f}x"
        )
    print(f"  load average (other work)   {os.getloadavg()[0]:6.1f} on {os.cpu_count()} cores")
    if sent and stats:
        print(f"  serialize / frame           {1e3 * stats.serialize_s / sent:6.2f} ms")
        print(
            f"  Zenoh put / frame           {1e3 * stats.put_s / sent:6.2f} ms "
            "(sender thread; blocks while the link is busy)"
        )
    if ages:
        print(
            f"  age of delivered frames     max {1e3 * max(ages):.0f} ms, "
            f"mean {1e3 * sum(ages) / len(ages):.0f} ms (wall clock)"
        )
        print(f"  simulation ahead on arrival max {max(lags):.3f} s simulated")
        last_stamp = max(stamp for _, stamp, _ in frames) / 1e9
        print(
            f"  newest frame delivered      stamped {last_stamp:.3f} s "
            f"(simulation ended at {args.seconds:g} s)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
