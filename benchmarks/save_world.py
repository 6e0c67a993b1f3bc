"""Saving the simulated world (``/gazebo/save_world``, File > Save World As): how long a save
of a ~50-model world takes, how long the simulation's thread is held for it, and whether the
simulation keeps its pace while saves run back to back.

The world: the ground plane and the sun, 40 crates included from a model directory made here
(dynamic, resting on the floor), 10 inline static walls, and the course's laser mbot driving
in a circle (360-beam scan at 5.5 Hz, 1 kHz physics). References measured in the same run:
reading the saved file back (``read_world``), and the simulation's real-time factor with no
save running.

    python benchmarks/save_world.py [--seconds 5] [--saves 20]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import PhysicsSimulation, save_world, snapshot
from belvedere.world import ModelPaths, read_world, read_world_string, world_sdf, write_world

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
LASER_MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"

CRATE = """<?xml version="1.0"?>
<sdf version="1.6"><model name="crate"><link name="link"><pose>0 0 0.2 0 0 0</pose>
<inertial><mass>2</mass><inertia><ixx>0.05</ixx><iyy>0.05</iyy><izz>0.05</izz></inertia>
</inertial>
<collision name="collision"><geometry><box><size>0.4 0.4 0.4</size></box></geometry></collision>
<visual name="visual"><geometry><box><size>0.4 0.4 0.4</size></box></geometry></visual>
</link></model></sdf>
"""


def _world_text() -> str:
    parts = [
        '<sdf version="1.6"><world name="crates">',
        "<include><uri>model://ground_plane</uri></include>",
        "<include><uri>model://sun</uri></include>",
    ]
    for i in range(40):
        x, y = -9.0 + 2.0 * (i % 10), 4.0 + 1.5 * (i // 10)
        parts.append(
            f"<include><uri>model://crate</uri><name>crate_{i}</name>"
            f"<pose>{x} {y} 0 0 0 {0.1 * i}</pose></include>"
        )
    for i in range(10):
        box = "<geometry><box><size>2 0.1 1</size></box></geometry>"
        parts.append(
            f"<model name='wall_{i}'><static>true</static><pose>{-9 + 2 * i} -4 0.5 0 0 0</pose>"
            f"<link name='link'><collision name='c'>{box}</collision>"
            f"<visual name='v'>{box}</visual></link></model>"
        )
    parts.append("</world></sdf>")
    return "\n".join(parts)


def _scene(root: Path) -> tuple[Graph, PhysicsSimulation, ModelPaths]:
    crate = root / "models" / "crate"
    crate.mkdir(parents=True)
    (crate / "model.sdf").write_text(CRATE)
    paths = ModelPaths((root / "models",))
    world = read_world_string(_world_text(), str(root / "crates.world"), model_paths=paths)
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    sim = PhysicsSimulation(graph, world)
    sim.spawn(RobotModel.from_path(LASER_MBOT), name="mbot", packages=packages)
    probe = graph.create_node("probe")
    probe.subscribe("/scan", "sensor_msgs/LaserScan", lambda _: None, queue_size=0)
    cmd = probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    cmd.publish_data({"linear": {"x": 0.2}, "angular": {"z": 0.3}})
    graph.run(duration=0.5, rtf=None)  # settle
    return graph, sim, paths


def _ms(samples: list[float]) -> str:
    return f"median {1e3 * statistics.median(samples):.2f} ms (min {1e3 * min(samples):.2f})"


def _timed(fn: Callable[[], object], n: int) -> list[float]:
    out = []
    for _ in range(n):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return out


def _rtf(
    graph: Graph, seconds: float, saving: Callable[[], object] | None, every: float = 0.0
) -> tuple[float, int]:
    """Simulated seconds per wall second over ``seconds`` of wall time (the graph running on
    its thread), with ``saving`` called on this thread meanwhile, every ``every`` seconds (0:
    back to back)."""
    saves = 0
    sim_start, wall_start = graph.now_ns(), time.perf_counter()
    while time.perf_counter() - wall_start < seconds:
        if saving is None:
            time.sleep(0.05)
            continue
        started = time.perf_counter()
        saving()
        saves += 1
        time.sleep(max(0.0, every - (time.perf_counter() - started)))
    return (graph.now_ns() - sim_start) / 1e9 / (time.perf_counter() - wall_start), saves


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--seconds", type=float, default=5.0, help="wall seconds per RTF run")
    parser.add_argument("--saves", type=int, default=20, help="saves timed")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        graph, sim, paths = _scene(root)
        target = root / "saved.world"
        print(f"world: {len(sim.model_names())} models ({len(sim.world.models)} world + robot)")

        # The parts of one save, the graph stopped (this thread is the simulation's).
        held = _timed(lambda: snapshot(sim), args.saves)
        shot = snapshot(sim)
        convert = _timed(shot.world_model, args.saves)
        world = shot.world_model()
        text = _timed(lambda: world_sdf(world, shot.state), args.saves)
        write = _timed(lambda: write_world(target, world, shot.state), args.saves)
        total = _timed(lambda: save_world(sim, target), args.saves)
        size = target.stat().st_size
        reload = _timed(lambda: read_world(target, model_paths=paths), args.saves)
        print(f"simulation thread held (snapshot): {_ms(held)}")
        print(f"poses, robot to SDF:              {_ms(convert)}")
        print(f"SDF text:                         {_ms(text)}")
        print(f"text + atomic write (fsync):      {_ms(write)}")
        print(f"whole save:                       {_ms(total)}; {size / 1024:.0f} KiB")
        print(f"reference, reading it back:       {_ms(reload)}")
        print(
            f"save / read ratio: {statistics.median(total) / statistics.median(reload):.2f}; "
            f"thread held / one 1 kHz step: {statistics.median(held) / 1e-3:.2f}"
        )

        graph.start(rtf=1.0)
        for label, rtf in (("paced 1x", 1.0), ("as fast as possible", None)):
            graph.executor.set_rtf(rtf)
            idle, _ = _rtf(graph, args.seconds, None)
            print(f"{label}: real-time factor {idle:.3f} without saving")
            for every, how in ((1.0, "one save a second"), (0.0, "saves back to back")):
                busy, saves = _rtf(graph, args.seconds, lambda: save_world(sim, target), every)
                print(f"  {busy:.3f} with {how} ({saves} saves; ratio {busy / idle:.3f})")
        graph.shutdown()


if __name__ == "__main__":
    main()
