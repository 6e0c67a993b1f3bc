"""How the physics simulation's cost grows with the number of robots.

N copies of the course's mbot with its laser (examples/mbot_gazebo/launch/namespaced_mbot.launch,
included once per robot as multi_mbot.launch does: ``<group ns="robot_i">``, its own
robot_description, tf_prefix, joint/robot state publishers and spawn_model) in the empty
world, on a grid 2 m apart, each driven in a circle by its own ``/robot_i/cmd_vel``, with a
subscriber to each ``/robot_i/scan`` (the lasers cast only while someone listens), each
``/robot_i/odom`` and ``/tf``. Headless at the maximum rate (rtf max).

Each N runs in a process of its own (so memory is its own). The steady state is a long run
minus a short run on the same world, so start-up (xacro, MuJoCo compiles, spawns) does not
count: wall and CPU seconds per simulated second over the difference. Reported: real-time
factor (by the wall clock, and by this process's CPU time: what it would be on an idle core,
as other work on a shared machine stretches the wall clock), CPU milliseconds per robot per
simulated second, peak RSS, and the ratio of cost per robot at N against N = 1 measured in
the same run (goal: <= 1.2 up to 20; 10 robots >= 5x real time).

    python benchmarks/many_robots.py [--robots 1 2 5 10 20] [--short 2] [--long 12] [--rounds 3]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
SPACING = 2.0


def launch_text(n: int) -> str:
    """multi_mbot.launch's shape for n robots, in the empty world."""
    columns = max(1, round(n**0.5))
    robots = []
    for i in range(n):
        x, y = SPACING * (i % columns), SPACING * (i // columns)
        robots.append(
            '  <include file="$(find mbot_gazebo)/launch/namespaced_mbot.launch">\n'
            f'    <arg name="robot_name" value="robot_{i + 1}"/>\n'
            f'    <arg name="x" value="{x}"/>\n    <arg name="y" value="{y}"/>\n'
            "  </include>\n"
        )
    return (
        "<launch>\n"
        '  <include file="$(find gazebo_ros)/launch/empty_world.launch">\n'
        '    <arg name="gui" value="false"/>\n    <arg name="headless" value="true"/>\n'
        "  </include>\n" + "".join(robots) + "</launch>\n"
    )


def measure(n: int, short: float, long: float) -> dict[str, float]:
    """In this process: start n robots, run short then long simulated seconds."""
    from belvedere.graph import Graph
    from belvedere.launch import load_launch
    from belvedere.launch._runtime import LaunchRuntime
    from belvedere.packages import PackageIndex

    packages = PackageIndex([EXAMPLES])
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "many.launch"
        path.write_text(launch_text(n))
        config = load_launch(path, packages=packages)
    graph = Graph()
    runtime = LaunchRuntime(config, graph, packages, headless=True)
    runtime.start()
    if runtime.missing:
        msg = f"missing nodes: {runtime.missing}"
        raise SystemExit(msg)
    probe = graph.create_node("probe")
    got = {"scan": 0, "odom": 0, "tf": 0}

    def counter(key: str) -> Callable[[object], None]:
        def count(_: object) -> None:
            got[key] += 1

        return count

    for i in range(1, n + 1):
        probe.subscribe(f"/robot_{i}/scan", "sensor_msgs/LaserScan", counter("scan"))
        probe.subscribe(f"/robot_{i}/odom", "nav_msgs/Odometry", counter("odom"))
        cmd = probe.publisher(f"/robot_{i}/cmd_vel", "geometry_msgs/Twist", latch=True)
        cmd.publish_data({"linear": {"x": 0.2}, "angular": {"z": 0.4}})
    probe.subscribe("/tf", "tf2_msgs/TFMessage", counter("tf"))
    graph.run(duration=0.5, rtf=None)  # everything spawned and subscribed
    marks = []
    for seconds in (short, long):
        wall, cpu = time.perf_counter(), time.process_time()
        graph.run(duration=seconds, rtf=None)
        marks.append((time.perf_counter() - wall, time.process_time() - cpu))
    sim_seconds = long - short
    wall = (marks[1][0] - marks[0][0]) / sim_seconds
    cpu = (marks[1][1] - marks[0][1]) / sim_seconds
    scans_expected = 5.5 * n * (short + long)
    if got["scan"] < 0.8 * scans_expected:
        msg = f"{n} robots: {got['scan']} scans, expected ~{scans_expected:.0f}"
        raise SystemExit(msg)
    runtime.close()
    graph.shutdown()
    return {
        "robots": n,
        "rtf": 1.0 / wall,
        "wall_per_sim_s": wall,
        "cpu_per_sim_s": cpu,
        "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "scans": got["scan"],
    }


def _run_one(n: int, short: float, long: float) -> dict[str, float]:
    """:func:`measure` in a process of its own."""
    out = subprocess.run(
        [sys.executable, __file__, "--one", str(n), "--short", str(short), "--long", str(long)],
        check=True,
        capture_output=True,
        text=True,
    )
    row: dict[str, float] = json.loads(out.stdout.strip().splitlines()[-1])
    return row


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--robots", type=int, nargs="+", default=[1, 2, 5, 10, 20])
    p.add_argument("--short", type=float, default=2.0, help="simulated seconds")
    p.add_argument("--long", type=float, default=12.0, help="simulated seconds")
    p.add_argument("--rounds", type=int, default=3, help="interleaved rounds (median)")
    p.add_argument("--one", type=int, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.one is not None:
        print(json.dumps(measure(args.one, args.short, args.long)))
        return
    # Rounds interleave the sizes, so a busy moment on a shared machine falls on all of
    # them; each size's row is its median round (by CPU time).
    runs: dict[int, list[dict[str, float]]] = {n: [] for n in args.robots}
    for _ in range(args.rounds):
        for n in args.robots:
            runs[n].append(_run_one(n, args.short, args.long))
    rows = [
        sorted(runs[n], key=lambda r: r["cpu_per_sim_s"])[len(runs[n]) // 2] for n in args.robots
    ]
    base = rows[0]["cpu_per_sim_s"] / rows[0]["robots"]
    print(
        f"steady state over {args.long - args.short:g} simulated s (long - short run),"
        f" median of {args.rounds} interleaved rounds"
    )
    print(
        f"{'robots':>6} {'RTF':>7} {'RTF(CPU)':>8} {'CPU ms/robot/sim s':>19}"
        f" {'per robot vs 1':>15}"
        f" {'RSS MB':>7} {'RSS MB/robot':>12}"
    )
    base_rss = rows[0]["rss_mb"]
    for row in rows:
        n = row["robots"]
        per_robot = row["cpu_per_sim_s"] / n
        extra = (row["rss_mb"] - base_rss) / (n - 1) if n > 1 else 0.0
        print(
            f"{n:>6} {row['rtf']:>6.1f}x {1.0 / row['cpu_per_sim_s']:>7.1f}x"
            f" {per_robot * 1000:>19.1f} {per_robot / base:>14.2f}x"
            f" {row['rss_mb']:>7.0f} {extra:>12.1f}"
        )


if __name__ == "__main__":
    main()
