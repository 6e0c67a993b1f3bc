"""The physics engine's speed. Gazebo classic runs the course's worlds at (at most) 1x real
time by default (real_time_update_rate 1000 with max_step_size 0.001); our reference here is
bare MuJoCo stepping the same compiled model in a loop, measured in the same run.

1. The course's mbot driving in the playground world, 1 kHz physics, 100 Hz diff drive, with
   an /odom subscriber: simulated seconds per wall second at rtf=max, and the ratio against
   bare ``mj_step`` on the same model (the cost of the graph, plugins and messages).
2. The laser mbot: a 360-beam scan at 5.5 Hz on top (with a /scan subscriber).
3. A camera mbot rendering 1280x720 images at 30 Hz while subscribed (offscreen, EGL).
4. The laser mbot in a room of 20 boxes, against a *minimal* MuJoCo loop written for it here
   (what a hand-written simulator of the same robot would cost): a cylinder base and two
   velocity-actuated wheels of the mbot's sizes and masses, two frictionless caster spheres,
   the same 20 boxes, a 360-ray ``mj_multiRay`` at 5.5 Hz and 100 Hz wheel control. Steady
   state: each side's rate is (long - short) simulated seconds over the difference of the
   two runs' CPU times (the process's own, so that other work on a shared machine counts
   less than in wall time), so start-up does not count; the sides alternate run by run.

    python benchmarks/physics.py [--seconds 20] [--only room] [--rounds 9]
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


def _scene(
    model_file: str, topics: dict[str, str], world: Path = WORLD
) -> tuple[Graph, PhysicsSimulation]:
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world(world, packages=packages))
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


# A 10 m x 10 m room: 4 walls and 16 pillars/crates, 20 static boxes (x, y, sx, sy, height).
ROOM_BOXES = [
    (0.0, 5.0, 10.2, 0.2, 1.0),
    (0.0, -5.0, 10.2, 0.2, 1.0),
    (5.0, 0.0, 0.2, 10.2, 1.0),
    (-5.0, 0.0, 0.2, 10.2, 1.0),
    *(
        (-3.0 + 2.0 * (i % 4), -3.0 + 2.0 * (i // 4), 0.3 + 0.1 * (i % 3), 0.4, 0.5)
        for i in range(16)
    ),
]


def room_world(path: Path) -> Path:
    """The room as a Gazebo world (1 kHz physics, sun, ground plane)."""
    models = "".join(
        f"""
    <model name="box{i}"><static>true</static><pose>{x} {y} {h / 2} 0 0 0</pose>
      <link name="link">
        <collision name="c"><geometry><box><size>{sx} {sy} {h}</size></box></geometry></collision>
        <visual name="v"><geometry><box><size>{sx} {sy} {h}</size></box></geometry></visual>
      </link></model>"""
        for i, (x, y, sx, sy, h) in enumerate(ROOM_BOXES)
    )
    path.write_text(
        f"""<?xml version="1.0"?>
<sdf version="1.6"><world name="room">
  <include><uri>model://sun</uri></include>
  <include><uri>model://ground_plane</uri></include>
  <physics type="ode"><max_step_size>0.001</max_step_size>
    <real_time_update_rate>1000</real_time_update_rate></physics>{models}
</world></sdf>
"""
    )
    return path


def minimal_mjcf() -> str:
    """The mbot as few MuJoCo elements as can stand for it, in the same room."""
    boxes = "".join(
        f'<geom type="box" pos="{x} {y} {h / 2}" size="{sx / 2} {sy / 2} {h / 2}"/>'
        for x, y, sx, sy, h in ROOM_BOXES
    )
    return f"""<mujoco>
  <option timestep="0.001" integrator="implicitfast"/>
  <worldbody>
    <geom type="plane" size="0 0 1"/>{boxes}
    <body name="base" pos="0 0 0.11">
      <freejoint/>
      <geom type="cylinder" size="0.2 0.08" mass="20"/>
      <site name="lidar" pos="0 0 0.13"/>
      <body pos="0 0.19 -0.05"><joint name="left" axis="0 1 0"/>
        <geom type="cylinder" size="0.06 0.0125" euler="90 0 0" mass="2"/></body>
      <body pos="0 -0.19 -0.05"><joint name="right" axis="0 1 0"/>
        <geom type="cylinder" size="0.06 0.0125" euler="90 0 0" mass="2"/></body>
      <geom type="sphere" size="0.015" pos="0.18 0 -0.095" friction="0 0 0" priority="1"
        condim="1" mass="0.5"/>
      <geom type="sphere" size="0.015" pos="-0.18 0 -0.095" friction="0 0 0" priority="1"
        condim="1" mass="0.5"/>
    </body>
  </worldbody>
  <actuator>
    <velocity joint="left" kv="30" forcerange="-30 30"/>
    <velocity joint="right" kv="30" forcerange="-30 30"/>
  </actuator>
</mujoco>"""


def minimal_loop(seconds: float) -> float:
    """CPU seconds the minimal loop takes for ``seconds`` of simulated time: the same drive
    command as the graph's, 100 Hz control, a 360-ray scan at 5.5 Hz."""
    import numpy as np

    mujoco = importlib.import_module("mujoco")
    m = mujoco.MjModel.from_xml_string(minimal_mjcf())
    d = mujoco.MjData(m)
    base = m.body("base").id
    site = m.site("lidar").id
    angles = np.linspace(-np.pi, np.pi, 360, endpoint=False)
    local = np.stack([np.cos(angles), np.sin(angles), np.zeros(360)], axis=1)
    geomid = np.zeros(360, np.int32)
    dist = np.zeros(360)
    v, w, half, radius = 0.2, 0.3, 0.19, 0.06
    steps = round(seconds / m.opt.timestep)
    scan_every = 1.0 / 5.5
    next_scan = 0.0
    started = time.process_time()
    for step in range(steps):
        if step % 10 == 0:
            d.ctrl[0] = (v - w * half) / radius
            d.ctrl[1] = (v + w * half) / radius
        if d.time >= next_scan:
            next_scan += scan_every
            rays = local @ d.site_xmat[site].reshape(3, 3).T
            mujoco.mj_multiRay(
                m, d, d.site_xpos[site], rays.ravel(), None, 1, base, geomid, dist, None, 360, 6.0
            )
        mujoco.mj_step(m, d)
    return time.process_time() - started


def ours_room(world: Path, seconds: float) -> float:
    """CPU seconds the graph takes for ``seconds`` of simulated time (the scene built first,
    not counted)."""
    topics = {"/odom": "nav_msgs/Odometry", "/scan": "sensor_msgs/LaserScan"}
    graph, _ = _scene("mbot_with_laser_gazebo.xacro", topics, world)
    started = time.process_time()
    graph.run(duration=seconds, rtf=None)
    took = time.process_time() - started
    graph.shutdown()
    return took


def steady_round(world: Path, short: float, long: float) -> tuple[float, float]:
    """One round, interleaved: each side's short run, then each side's long run. The steady
    rate is the extra simulated time of the long run over its extra CPU time, so what only
    the start costs (the first messages' types, caches, the first contacts) does not count."""
    ours_short = ours_room(world, short)
    minimal_short = minimal_loop(short)
    ours_long = ours_room(world, long)
    minimal_long = minimal_loop(long)
    extra = long - short
    return extra / max(ours_long - ours_short, 1e-9), extra / max(
        minimal_long - minimal_short, 1e-9
    )


def room_rounds(seconds: float, rounds: int) -> None:
    """Ours and the minimal loop in steady state, interleaved, ``rounds`` times: the median of
    the paired ratios holds on a busy machine."""
    import tempfile

    short = seconds / 5
    with tempfile.TemporaryDirectory() as tmp:
        world = room_world(Path(tmp) / "room.world")
        pairs = [steady_round(world, short, seconds) for _ in range(rounds)]
    ratios = sorted(ours / minimal for ours, minimal in pairs)
    ours, minimal = sorted(pairs, key=lambda p: p[0] / p[1])[len(pairs) // 2]
    print(
        f"{'mbot + laser, 20-box room':26s} {ours:7.1f}x real time per CPU second   minimal loop "
        f"{minimal:7.1f}x"
        f"   steady ratio {ratios[len(ratios) // 2]:.2f} (median of {rounds}, "
        f"{ratios[0]:.2f}-{ratios[-1]:.2f}; {seconds:g} s minus {short:g} s runs)"
        "   (goal: at least 0.8)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--only", choices=["room"], help="run only the room case")
    parser.add_argument("--rounds", type=int, default=9, help="paired rounds of the room case")
    args = parser.parse_args()
    if args.only != "room":
        _bare_cases(args.seconds)
    room_rounds(args.seconds, args.rounds)


def _bare_cases(seconds_wanted: float) -> None:
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
        seconds = seconds_wanted if "camera" not in label else min(seconds_wanted, 2.0)
        ours, bare = run(model_file, topics, seconds)
        print(
            f"{label:26s} {ours:7.1f}x real time   bare mj_step {bare:7.1f}x   "
            f"ratio {ours / bare:.2f}   (Gazebo classic: 1x by default)"
        )


if __name__ == "__main__":
    main()
