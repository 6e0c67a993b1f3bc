"""``belvedere sim MODEL``: drive a robot with ``/cmd_vel`` and watch it in the browser.

``--engine kinematic``: ArbotiX fake mode + robot_state_publisher + joint_state_publisher.
``--engine physics``: MuJoCo in a world (``--world``), the robot's Gazebo plugins, gazebo_ros's
services, robot_state_publisher + joint_state_publisher — the course's Gazebo launch.
Scripted runs: ``--headless --rtf max --duration 10 --pub '…' --echo /odom``.
"""

from __future__ import annotations

import argparse
import sys
import time
import webbrowser
from typing import TYPE_CHECKING

from belvedere.cli._args import add_viewer_options, mappings_only
from belvedere.cli._foxglove import add_foxglove_options, bridge_options
from belvedere.cli._report import notice, report_diagnostics, report_lines
from belvedere.cli._script import add_script_options, script_options
from belvedere.cli._tool import add_graph_options, graph_address
from belvedere.description.urdf import Pose, RobotModel
from belvedere.errors import BelvedereError, ParseError
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.runtime import install_script, open_clock_transport, start_bridge
from belvedere.sim import (
    DEFAULT_MAX_SPEED,
    DEFAULT_MAX_TURN_RATE,
    MAX_SPEED_PARAM,
    MAX_TURN_RATE_PARAM,
)
from belvedere.sim.kinematic import ArbotixConfig, KinematicSimulation
from belvedere.sim.physics import GazeboRos, PhysicsSimulation, name_taken
from belvedere.tf import JointStatePublisher, RobotStatePublisher
from belvedere.world import ModelPaths, WorldModel, empty_world, read_world
from belvedere.yamlfile import load_yaml_file

if TYPE_CHECKING:
    from belvedere.foxglove import FoxgloveBridge
    from belvedere.viewer import Viewer

Simulation = KinematicSimulation | PhysicsSimulation

__all__ = ["add_parser", "run"]

ENGINES = ("kinematic", "physics")


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "sim",
        parents=[common],
        help="simulate a robot driven by /cmd_vel",
        description="Simulate a robot model. The kinematic engine is ArbotiX's fake mode: the "
        "base moves exactly as /cmd_vel says (and keeps moving until a zero Twist arrives, as "
        "the original does; see --cmd-vel-timeout).",
    )
    p.add_argument("input", metavar="MODEL", help="URDF or xacro file (then name:=value args)")
    p.add_argument(
        "--engine",
        choices=ENGINES,
        help="default: kinematic, or physics with --world or --paused",
    )
    p.add_argument(
        "--config", metavar="YAML", help="ArbotiX driver parameters (e.g. fake_mbot_arbotix.yaml)"
    )
    p.add_argument(
        "--namespace", default="/", metavar="NS", help="run the robot's nodes and topics under NS"
    )
    p.add_argument(
        "--cmd-vel-timeout",
        type=float,
        metavar="SECONDS",
        help="stop the base after SECONDS without a command (default: never, as ArbotiX)",
    )
    p.add_argument(
        "--max-speed",
        type=float,
        metavar="M/S",
        help=f"ignore velocity commands faster than this (default: {DEFAULT_MAX_SPEED:g}; "
        f"the parameter {MAX_SPEED_PARAM})",
    )
    p.add_argument(
        "--max-turn-rate",
        type=float,
        metavar="RAD/S",
        help=f"ignore angular velocity commands beyond this (default: {DEFAULT_MAX_TURN_RATE:g};"
        f" the parameter {MAX_TURN_RATE_PARAM})",
    )
    p.add_argument("--seed", type=int, default=0, help="seed of the simulation's randomness")
    p.add_argument("--world", metavar="FILE", help="physics: a Gazebo .world file (default: empty)")
    for axis, what in (("x", "x (m)"), ("y", "y (m)"), ("z", "z (m)")):
        p.add_argument(f"-{axis}", type=float, default=0.0, help=f"physics: spawn at {what}")
    for axis, what in (("R", "roll"), ("P", "pitch"), ("Y", "yaw")):
        p.add_argument(f"-{axis}", type=float, default=0.0, help=f"physics: spawn {what} (rad)")
    p.add_argument("--paused", action="store_true", help="physics: start paused")
    p.add_argument(
        "--auto-reset", action="store_true", help="physics: reset the world if it diverges"
    )
    p.add_argument("--headless", action="store_true", help="no viewer")
    p.add_argument("--rviz", metavar="CONFIG", help="an rviz .rviz config for the viewer")
    add_viewer_options(p)
    p.add_argument("--open", action="store_true", help="open a browser on the viewer")
    add_foxglove_options(p)
    add_script_options(p)
    add_graph_options(p)
    p.set_defaults(run=run)


def load_config(path: str) -> tuple[ArbotixConfig, dict[str, object]]:
    """The driver's config and its raw parameters, from a YAML file."""
    doc = load_yaml_file(path)
    if doc.data is not None and not isinstance(doc.data, dict):
        msg = f"{path}: ArbotiX parameters must be a mapping (rate:, controllers:, joints: …)"
        raise BelvedereError(msg)
    return ArbotixConfig.from_yaml(doc), dict(doc.data or {})


def run(args: argparse.Namespace) -> int:
    mappings = mappings_only(list(args.extra))
    script = script_options(args)
    if args.engine is None:
        args.engine = "kinematic"
        implied = [o for o, given in (("--world", args.world), ("--paused", args.paused)) if given]
        if implied:
            args.engine = "physics"
            notice(f"note: {' and '.join(implied)} implies --engine physics")
    if args.engine == "kinematic" and (args.world or args.paused):
        msg = "--world and --paused are for --engine physics, not kinematic"
        raise BelvedereError(msg)
    if args.paused and args.duration is not None:
        # --duration is simulated time: paused, it passes only once something unpauses
        notice(
            "note: paused, --duration counts from when the simulation runs "
            "(belvedere service call /gazebo/unpause_physics, or the viewer's Paused box)"
        )
    if args.engine == "physics" and (args.config or args.namespace != "/"):
        msg = "--config and --namespace are for --engine kinematic"
        raise BelvedereError(
            msg, hint="with physics, the model's <gazebo> plugins say what drives it"
        )
    config, params = load_config(args.config) if args.config else (None, {})
    packages = PackageIndex.from_environment(package_path=args.package_path, near=args.input)
    model = RobotModel.from_path(args.input, mappings=mappings, packages=packages)
    report_diagnostics(model.warnings, source=args.input)
    world = _read_world(args, packages) if args.engine == "physics" else None
    transport = open_clock_transport(graph_address(args))
    graph = Graph(sim_time=True, seed=args.seed, transport=transport)
    for param, value in (
        (MAX_SPEED_PARAM, args.max_speed),
        (MAX_TURN_RATE_PARAM, args.max_turn_rate),
    ):
        if value is not None:
            graph.params.set(param, value)
    viewer: Viewer | None = None
    bridge: FoxgloveBridge | None = None
    try:
        if world is not None:
            sim: Simulation = _physics(args, graph, model, world, packages)
        else:
            sim = _kinematic(args, graph, model, config, params)
        install_script(graph, script)
        if args.paused:
            graph.executor.pause(True)
        bridge = start_bridge(graph, bridge_options(args))
        if not args.headless:
            viewer = _open_viewer(args, graph, model, sim, packages, world)
        _run(graph, args)
    except KeyboardInterrupt:
        pass
    finally:
        sys.stdout.flush()
        if bridge is not None:
            bridge.close()
        if viewer is not None:
            viewer.close()
        graph.shutdown()
    return 0


def _kinematic(
    args: argparse.Namespace,
    graph: Graph,
    model: RobotModel,
    config: ArbotixConfig | None,
    params: dict[str, object],
) -> KinematicSimulation:
    sim = KinematicSimulation(
        graph,
        model,
        config,
        params=params,
        namespace=args.namespace,
        cmd_vel_timeout=args.cmd_vel_timeout,
    )
    if config is None:
        base = sim.driver.base
        notice(
            "no --config: a diff_controller drives "
            f"{base.base_frame if base else '?'} (odom frame {sim.odom_frame})"
        )
    return sim


def _read_world(args: argparse.Namespace, packages: PackageIndex) -> WorldModel:
    if args.world:
        world = read_world(args.world, packages=packages)
    else:
        world = empty_world(model_paths=ModelPaths.from_environment(packages=packages))
    report_lines(world.warnings)
    return world


def _physics(
    args: argparse.Namespace,
    graph: Graph,
    model: RobotModel,
    world: WorldModel,
    packages: PackageIndex,
) -> PhysicsSimulation:
    embedded = world.model(model.name)
    if embedded is not None:  # Gazebo refuses to spawn a second model of one name
        msg = (
            f"{name_taken(model.name)} The world already has a model named {model.name!r}; "
            f"the robot {model.path or model.name} cannot be spawned under that name again"
        )
        raise ParseError(
            msg,
            embedded.source,
            hint="a world saved while the robot was in it keeps the robot, and it runs as it "
            "did: run the world alone (belvedere launch gazebo_ros empty_world.launch "
            f"world_name:={world.path}), or remove that <model> from the world file",
        )
    sim = PhysicsSimulation(graph, world, auto_reset=args.auto_reset)
    GazeboRos(sim, packages=packages)
    graph.params.set("/robot_description", model.to_urdf())
    pose = Pose((args.x, args.y, args.z), (args.R, args.P, args.Y))
    robot = sim.spawn(model, name=model.name, pose=pose, packages=packages)
    RobotStatePublisher(graph.create_node("robot_state_publisher"), model)
    JointStatePublisher(
        graph.create_node("joint_state_publisher"), model, exclude=robot.published_joints()
    )
    return sim


def _open_viewer(
    args: argparse.Namespace,
    graph: Graph,
    model: RobotModel,
    sim: Simulation,
    packages: PackageIndex,
    world: WorldModel | None,
) -> Viewer:
    from belvedere.viewer import Viewer, read_rviz

    viewer = Viewer(
        graph,
        model=model,
        host=args.host,
        port=args.port,
        allow_origins=args.allow_origins,
        fixed_frame=None if args.rviz else sim.odom_frame,
        rviz=read_rviz(args.rviz) if args.rviz else None,
        rviz_path=args.rviz,
        sim=sim,
        packages=packages,
        world=world,
        world_poses=sim.model_poses if isinstance(sim, PhysicsSimulation) else None,
    )
    if isinstance(sim, PhysicsSimulation) and not args.rviz:
        for kind, topic in sim.sensor_topics():
            viewer.add_display(kind, topic)
    sys.stderr.write(f"viewer: {viewer.url} (Ctrl-C to stop)\n")
    if args.open:
        webbrowser.open(viewer.url)
    return viewer


def _run(graph: Graph, args: argparse.Namespace) -> None:
    started = time.monotonic()
    graph.run(duration=args.duration, rtf=args.rtf)
    if args.duration is not None:
        wall = time.monotonic() - started
        rate = args.duration / wall if wall > 0 else float("inf")
        notice(f"simulated {args.duration:g} s in {wall:.3f} s ({rate:.0f}x real time)")
