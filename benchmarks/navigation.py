"""Navigation to seeded random reachable goals, in the course's two set-ups:

- ``physics``: the mbot with its laser in the cloister (mbot_gazebo's mbot_laser_nav_gazebo
  launch) with the course's nav_cloister_demo (map_server + amcl + move_base with
  TrajectoryPlannerROS) on the map belvedere made of it;
- ``fake``: rbx1's fake TurtleBot (ArbotiX) with fake_move_base_blank_map on the blank map.

For each goal (``--goals``, default 20, drawn from the map's free cells at least 0.45 m from
a wall and reachable from the start): whether move_base succeeded and the robot stands within
the local planner's tolerances, the simulated time it took, the driven path's length against
the shortest 8-connected grid path, and (physics) the robot's least clearance from the map's
walls against its radius. Then the planners timed on their own against their periods: the
global planner across the map at ``planner_frequency`` (or 1 Hz) and the local planner's cycle
at ``controller_frequency``, on the grids move_base had.

Run: ``python benchmarks/navigation.py [--goals N] [--setup physics|fake|both]``.
"""

from __future__ import annotations

import argparse
import heapq
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from belvedere.graph import ActionClient, GoalStatus, Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.maps import load_map
from belvedere.nav.costmap import CostGrid
from belvedere.nav.local import make_local_planner
from belvedere.nav.planners import make_global_planner
from belvedere.packages import PackageIndex
from belvedere.yamlfile import load_yaml_file

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

SETUPS: dict[str, dict[str, Any]] = {
    "physics": {
        "includes": [
            "mbot_gazebo/launch/mbot_laser_nav_gazebo.launch",
            "mbot_navigation/launch/nav_cloister_demo.launch",
        ],
        "map": "mbot_navigation/maps/cloister_gmapping.yaml",
        "params": "mbot_navigation/config/mbot/base_local_planner_params.yaml",
        "start": (0.0, -4.5),
        "radius": 0.2,
        "odom": "/odom",
    },
    "fake": {
        "includes": [
            "rbx1_bringup/launch/fake_turtlebot.launch",
            "rbx1_nav/launch/fake_move_base_blank_map.launch",
        ],
        "map": "rbx1_nav/maps/blank_map.yaml",
        "params": "rbx1_nav/config/fake/base_local_planner_params.yaml",
        "start": (0.0, 0.0),
        "radius": 0.2,
        "odom": "/odom",
    },
}


def _free_and_distance(map_yaml: Path) -> tuple[Any, npt.NDArray[np.bool_], npt.NDArray[Any]]:
    grid = load_map(map_yaml)
    free = grid.data == 0
    walls = grid.data == 100
    distance = ndimage.distance_transform_edt(~walls) * grid.resolution
    return grid, free, distance


def _cell(grid: Any, x: float, y: float) -> tuple[int, int]:
    return (
        math.floor((y - grid.origin[1]) / grid.resolution),
        math.floor((x - grid.origin[0]) / grid.resolution),
    )


def _shortest(
    passable: npt.NDArray[np.bool_], start: tuple[int, int], goal: tuple[int, int], res: float
) -> float:
    """The shortest 8-connected path's length (m) over ``passable`` cells."""
    best = {start: 0.0}
    queue = [(0.0, start)]
    steps = [(dr, dc, math.hypot(dr, dc)) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if dr or dc]
    while queue:
        d, (r, c) = heapq.heappop(queue)
        if (r, c) == goal:
            return d * res
        if d > best.get((r, c), math.inf):
            continue
        for dr, dc, w in steps:
            n = (r + dr, c + dc)
            if 0 <= n[0] < passable.shape[0] and 0 <= n[1] < passable.shape[1] and passable[n]:
                nd = d + w
                if nd < best.get(n, math.inf):
                    best[n] = nd
                    heapq.heappush(queue, (nd, n))
    return math.inf


def _goals(setup: dict[str, Any], count: int, seed: int) -> list[tuple[float, float, float]]:
    grid, free, distance = _free_and_distance(EXAMPLES / setup["map"])
    ok = free & (distance >= 0.45)
    labels, _ = ndimage.label(ok)
    start = _cell(grid, *setup["start"])
    reachable = labels == labels[start]
    rows, cols = np.nonzero(reachable)
    rng = np.random.default_rng(seed)
    goals = []
    for k in rng.choice(len(rows), size=count, replace=False):
        x = grid.origin[0] + (cols[k] + 0.5) * grid.resolution
        y = grid.origin[1] + (rows[k] + 0.5) * grid.resolution
        goals.append((float(x), float(y), float(rng.uniform(-math.pi, math.pi))))
    return goals


def _run(name: str, count: int, seed: int, tmp: Path) -> dict[str, Any]:
    setup = SETUPS[name]
    launch = tmp / f"{name}.launch"
    includes = "".join(f'  <include file="{EXAMPLES / i}"/>\n' for i in setup["includes"])
    launch.write_text(f"<launch>\n{includes}</launch>\n")
    packages = PackageIndex.from_environment(near=EXAMPLES / "mbot_navigation/package.xml")
    graph = Graph(seed=seed)
    runtime = LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True)
    runtime.start()
    probe = graph.create_node("bench")
    touches = _WallContacts(runtime.sim) if runtime.sim is not None else None
    if touches is not None:
        probe.timer(0.01, touches.sample)
    poses: list[tuple[float, float, float]] = []

    def on_odom(msg: Any) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        poses.append((p.x, p.y, 2 * math.atan2(q.z, q.w)))

    probe.subscribe(setup["odom"], "nav_msgs/Odometry", on_odom)
    client = ActionClient(probe, "/move_base", "move_base_msgs/MoveBase")
    graph.run(duration=2.0)
    grid, _free, distance = _free_and_distance(EXAMPLES / setup["map"])
    passable = distance >= setup["radius"]
    local = load_yaml_file(EXAMPLES / setup["params"]).data["TrajectoryPlannerROS"]
    rows = []
    wall_started = time.perf_counter()
    for x, y, yaw in _goals(setup, count, seed):
        here = poses[-1]
        began_ns, first = graph.now_ns(), len(poses)
        orientation = {"z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}
        goal = client.send_goal(
            {
                "target_pose": {
                    "header": {"frame_id": "map"},
                    "pose": {"position": {"x": x, "y": y}, "orientation": orientation},
                }
            }
        )
        graph.run(duration=240.0, until=lambda: client.done(goal))  # noqa: B023
        graph.run(duration=0.5)
        took = (graph.now_ns() - began_ns) / 1e9
        track = np.array(poses[first:])
        driven = float(np.hypot(*np.diff(track[:, :2], axis=0).T).sum()) if len(track) > 1 else 0.0
        shortest = _shortest(
            passable, _cell(grid, here[0], here[1]), _cell(grid, x, y), grid.resolution
        )
        end = poses[-1]
        error = math.hypot(end[0] - x, end[1] - y)
        turn = abs(math.remainder(end[2] - yaw, math.tau))
        cells = [_cell(grid, px, py) for px, py, _ in track]
        clearance = min(float(distance[c]) for c in cells) if cells else math.inf
        ok = client.status.get(goal) == GoalStatus.SUCCEEDED
        within = (
            error <= float(local["xy_goal_tolerance"]) * 1.5
            and turn <= float(local["yaw_goal_tolerance"]) * 1.5
        )
        rows.append((ok and within, took, driven, shortest, clearance, error, turn))
        status = GoalStatus(client.status.get(goal, GoalStatus.LOST)).name
        print(
            f"  goal {len(rows):2d} ({x:6.2f}, {y:6.2f}, {math.degrees(yaw):6.1f} deg): "
            f"{'reached' if ok and within else 'MISSED '} {status:<9} {took:6.1f} s, "
            f"off {error:.3f} m / {math.degrees(turn):5.1f} deg",
            flush=True,
        )
    wall = time.perf_counter() - wall_started
    graph.shutdown()
    return {
        "rows": rows,
        "wall": wall,
        "sim": graph.now_ns() / 1e9,
        "local": local,
        "grid": grid,
        "touches": touches,
    }


class _WallContacts:
    """The physics engine's own contacts between the robot and anything but the ground,
    sampled every 10 ms of simulated time: the truth the map-based clearance estimates."""

    def __init__(self, sim: Any) -> None:
        self.sim = sim
        self.samples = 0
        self.touching = 0
        self.deepest = 0.0

    def sample(self) -> None:
        import mujoco

        engine = self.sim.engine
        model, data = engine.model, engine.data
        robot: set[int] = set()
        for spawned in self.sim.robots.values():
            for body, _ in spawned.build.link_body.values():
                robot.add(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body))
        roots = {int(model.body_rootid[b]) for b in robot}
        self.samples += 1
        touched = False
        for contact in data.contact[: data.ncon]:
            g1, g2 = int(contact.geom[0]), int(contact.geom[1])
            b1, b2 = (int(model.body_rootid[model.geom_bodyid[g]]) for g in (g1, g2))
            if (b1 in roots) == (b2 in roots):
                continue
            other = g2 if b1 in roots else g1
            if model.geom_type[other] == mujoco.mjtGeom.mjGEOM_PLANE:
                continue  # the floor
            touched = True
            self.deepest = max(self.deepest, -float(contact.dist))
        self.touching += touched


def _config(setup: dict[str, Any], name: str) -> dict[str, Any]:
    folder = (EXAMPLES / setup["params"]).parent
    data = load_yaml_file(folder / f"{name}.yaml").data
    return data if isinstance(data, dict) else {}


def _footprint(setup: dict[str, Any]) -> npt.NDArray[np.float64]:
    """The costmaps' footprint: ``footprint`` when given, else a circle of ``robot_radius``."""
    common = _config(setup, "costmap_common_params")
    if "footprint" in common:
        return np.array(common["footprint"], dtype=np.float64)
    radius = float(common.get("robot_radius", 0.46))
    angles = np.linspace(0, math.tau, 16, endpoint=False)
    return radius * np.column_stack([np.cos(angles), np.sin(angles)])


def _planner_timing(setup: dict[str, Any], local_params: dict[str, Any]) -> tuple[float, float]:
    """Median wall seconds of a global plan across the map and of a local planner cycle (on
    the map's grid when the local costmap holds the static map, as the course's does, else on
    a free window of its size)."""
    grid_map = load_map(EXAMPLES / setup["map"])
    costs = np.where(grid_map.data == 100, 254, np.where(grid_map.data < 0, 255, 0)).astype(
        np.uint8
    )
    grid = CostGrid(costs, grid_map.resolution, grid_map.origin[0], grid_map.origin[1])
    planner = make_global_planner("navfn/NavfnROS", {})
    start = np.array([*setup["start"], 0.0])
    far = np.array(
        max(_goals(setup, 20, 1), key=lambda g: math.hypot(g[0] - start[0], g[1] - start[1]))
    )
    times = []
    plan = None
    for _ in range(5):
        t = time.perf_counter()
        plan = planner.plan(grid, start, far)
        times.append(time.perf_counter() - t)
    assert plan is not None
    frequency = float(_config(setup, "base_local_planner_params").get("controller_frequency", 20))
    controller = make_local_planner(
        "base_local_planner/TrajectoryPlannerROS",
        {"controller_frequency": frequency, **local_params},
    )
    controller.set_plan(plan)
    local = _config(setup, "local_costmap_params").get("local_costmap", {})
    if local.get("static_map") and not local.get("rolling_window"):
        window = grid
    else:
        side = round(float(local.get("width", 6.0)) / 0.05)
        window = CostGrid(
            np.zeros((side, side), dtype=np.uint8), 0.05, start[0] - 3.0, start[1] - 3.0
        )
    footprint = _footprint(setup)
    cycles = []
    for _ in range(20):
        t = time.perf_counter()
        controller.compute(window, start, np.zeros(3), footprint)
        cycles.append(time.perf_counter() - t)
    return float(np.median(times)), float(np.median(cycles))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--goals", type=int, default=20)
    parser.add_argument("--setup", choices=("physics", "fake", "both"), default="both")
    parser.add_argument("--seed", type=int, default=16)
    args = parser.parse_args()
    import tempfile

    names = ["physics", "fake"] if args.setup == "both" else [args.setup]
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            result = _run(name, args.goals, args.seed, Path(tmp))
            rows = result["rows"]
            reached = sum(r[0] for r in rows)
            ratio = [r[2] / r[3] for r in rows if r[0] and r[3] > 0.3 and math.isfinite(r[3])]
            print(f"{name}: {reached}/{len(rows)} goals reached within the tolerances")
            print(
                f"  time to goal (simulated): median {np.median([r[1] for r in rows]):.1f} s, "
                f"max {max(r[1] for r in rows):.1f} s"
            )
            if ratio:
                print(
                    f"  driven / shortest grid path: median {np.median(ratio):.2f}, "
                    f"max {max(ratio):.2f}"
                )
            print(
                f"  final error: max {max(r[5] for r in rows):.3f} m, "
                f"{math.degrees(max(r[6] for r in rows)):.1f} deg"
            )
            if name == "physics":
                least = min(r[4] for r in rows)
                radius = SETUPS[name]["radius"]
                print(
                    f"  least clearance from the map's wall cells (centres): {least:.3f} m "
                    f"(the body's radius {radius} m)"
                )
                touches = result["touches"]
                if touches is not None:
                    print(
                        f"  contacts with walls in the physics engine: {touches.touching} of "
                        f"{touches.samples} samples (10 ms), deepest "
                        f"{touches.deepest * 1000:.1f} mm: "
                        f"{'no contact' if touches.touching == 0 else 'CONTACT'}"
                    )
            print(
                f"  {result['sim']:.0f} s simulated in {result['wall']:.0f} s wall "
                f"(real-time factor {result['sim'] / result['wall']:.1f})"
            )
            plan_s, cycle_s = _planner_timing(SETUPS[name], result["local"])
            params = _config(SETUPS[name], "base_local_planner_params")
            frequency = float(params.get("controller_frequency", 20.0))
            print(
                f"  global plan across the map: {plan_s * 1000:.1f} ms "
                f"= {plan_s:.3f} of a 1 s planning period"
            )
            print(
                f"  local planner cycle: {cycle_s * 1000:.1f} ms = {cycle_s * frequency:.3f} "
                f"of the {1 / frequency:.2f} s control period"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
